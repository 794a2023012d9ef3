// The robust outlier scale and threshold (optim/estimation/robust_scale.hpp): the element of rank n/2
// over √(2 ln 2), against values worked by hand, and ≈ 1 for the norms of unit 2-D Gaussian noise.
#include "optim/estimation/robust_scale.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace rangecal {
namespace {

constexpr double kMedianOfChi2 = 1.1774100225154747;  // √(2 ln 2), the median of a χ₂ variable

TEST(RobustScale, IsTheMedianOverTheMedianOfAChi2Variable) {
  EXPECT_DOUBLE_EQ(robust_scale({3.0, 1.0, 2.0}), 2.0 / kMedianOfChi2);
  // Even count: the upper of the two middle elements.
  EXPECT_DOUBLE_EQ(robust_scale({4.0, 1.0, 3.0, 2.0}), 3.0 / kMedianOfChi2);
  EXPECT_DOUBLE_EQ(robust_scale({7.5}), 7.5 / kMedianOfChi2);
  EXPECT_EQ(robust_scale({}), 1.0);
}

TEST(RobustScale, IsOneForUnitGaussianNoise) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> gauss(0, 1);
  std::vector<double> norms;
  for (int i = 0; i < 200000; ++i) norms.push_back(std::hypot(gauss(rng), gauss(rng)));
  EXPECT_NEAR(robust_scale(norms), 1.0, 0.01);
  // Twice the noise doubles the scale.
  for (double& n : norms) n *= 2;
  EXPECT_NEAR(robust_scale(norms), 2.0, 0.02);
}

TEST(RobustScale, ThresholdIsKTimesTheScaleButNeverBelowK) {
  // Scale below 1 (an over-pessimistic σ): the threshold stays at k.
  EXPECT_DOUBLE_EQ(robust_outlier_threshold(3.5, {0.1, 0.2, 0.3}), 3.5);
  // Scale 2 / 1.17741 = 1.6986: k times it.
  EXPECT_DOUBLE_EQ(robust_outlier_threshold(3.5, {1.0, 2.0, 50.0}), 3.5 * 2.0 / kMedianOfChi2);
  EXPECT_DOUBLE_EQ(robust_outlier_threshold(4.0, {}), 4.0);
}

}  // namespace
}  // namespace rangecal
