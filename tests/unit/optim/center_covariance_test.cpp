// The camera centre's covariance (optim/estimation/center_covariance.hpp): the (CE, CN, CU) block of a
// result's covariance in ENU order whatever the parameters' order, zero rows and columns for a held
// coordinate, NaN without a covariance.
#include "optim/estimation/center_covariance.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace rangecal {
namespace {

using P = CameraParameter;

CalibrationResult result_with(const std::vector<CameraParameter>& parameters) {
  CalibrationResult r;
  r.parameters = parameters;
  const int n = static_cast<int>(parameters.size());
  r.covariance.resize(n, n);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) r.covariance(a, b) = 10 * (a + 1) + (b + 1);  // entry "ab"
  return r;
}

TEST(CenterCovariance, IsTheCentreBlockInEnuOrder) {
  // Parameters f, CU, CE, k1, CN: CE is index 2, CN 4, CU 1.
  const Eigen::Matrix3d cc = center_covariance(result_with({P::f, P::CU, P::CE, P::k1, P::CN}));
  Eigen::Matrix3d expected;
  expected << 33, 35, 32, 53, 55, 52, 23, 25, 22;
  EXPECT_EQ(cc, expected);
}

TEST(CenterCovariance, AHeldCoordinateHasZeroRowAndColumn) {
  const Eigen::Matrix3d cc = center_covariance(result_with({P::CE, P::CU}));
  Eigen::Matrix3d expected;
  expected << 11, 0, 12, 0, 0, 0, 21, 0, 22;
  EXPECT_EQ(cc, expected);
}

TEST(CenterCovariance, IsNanWithoutACovariance) {
  CalibrationResult r;
  r.parameters = {P::CE, P::CN, P::CU};
  EXPECT_TRUE(center_covariance(r).array().isNaN().all());
}

}  // namespace
}  // namespace rangecal
