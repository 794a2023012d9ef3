#include "vision/calibration/nearest_rotation.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>

namespace rangecal {
namespace {

TEST(NearestRotation, KeepsARotation) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  EXPECT_LT((nearest_rotation(R) - R).norm(), 1e-12);
}

// A rotation scaled and disturbed, as a linear solve returns it, comes back to the rotation.
TEST(NearestRotation, OrthonormalisesANoisyScaledRotation) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(-1.2, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
  Eigen::Matrix3d noise;
  noise << 1e-3, -2e-3, 0, 5e-4, 1e-3, -1e-3, 0, 2e-3, 3e-4;
  const Eigen::Matrix3d Q = nearest_rotation(1.7 * R + noise);
  EXPECT_LT((Q.transpose() * Q - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(Q.determinant(), 1, 1e-12);
  EXPECT_LT((Q - R).norm(), 3e-3);
}

// A reflection's nearest orthogonal matrix has det −1; the nearest rotation flips the weakest axis.
TEST(NearestRotation, NeverReturnsAReflection) {
  const Eigen::Matrix3d M = Eigen::Vector3d(1, 1, -0.1).asDiagonal();
  const Eigen::Matrix3d Q = nearest_rotation(M);
  EXPECT_NEAR(Q.determinant(), 1, 1e-12);
  EXPECT_LT((Q - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

}  // namespace
}  // namespace rangecal
