// The symmetric part of a matrix (optim/estimation/symmetric_part.hpp), against ½(M + Mᵀ) by hand.
#include "optim/estimation/symmetric_part.hpp"

#include <gtest/gtest.h>

namespace rangecal {
namespace {

TEST(SymmetricPart, AveragesTheTwoTriangles) {
  Eigen::Matrix3d m;
  m << 1, 2, 3, 4, 5, 6, 7, 8, 9;
  Eigen::Matrix3d expected;
  expected << 1, 3, 5, 3, 5, 7, 5, 7, 9;
  EXPECT_EQ(symmetric_part(m), expected);
  Eigen::MatrixXd dynamic = m;
  dynamic = symmetric_part(dynamic);  // in place, as the network's covariance uses it
  EXPECT_EQ(Eigen::Matrix3d(dynamic), expected);
}

}  // namespace
}  // namespace rangecal
