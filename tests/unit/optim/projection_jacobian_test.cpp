// The written-out projection derivatives (optim/bundle/projection_jacobian) against Ceres' automatic
// differentiation of the cost functor with the network's point block, which is the projection
// written like the equations (optim/bundle/reprojection_cost.hpp), and the pixel against vision's
// project(): every
// column of ∂(u, v)/∂(camera, world point), for rotations about R0 from zero to 0.4 rad, all seven
// distortion terms, sx ≠ 1, a clock offset and a moving lamp.
#include <gtest/gtest.h>

#include <ceres/ceres.h>

#include <Eigen/Geometry>
#include <random>

#include "optim/bundle/bundle_parameters.hpp"
#include "optim/bundle/projection_jacobian.hpp"
#include "optim/bundle/reprojection_cost_function.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using AutoDiffCost = ceres::AutoDiffCostFunction<ReprojectionResidual, 2, kIntrinsicsBlockSize,
                                                 kDistortionBlockSize, kPoseBlockSize, kClockBlockSize, 3>;

struct Case {
  double rotation_rad;  ///< |w| about R0
  bool distorted;       ///< all seven terms
};

class ProjectionJacobianTest : public ::testing::TestWithParam<Case> {};

TEST_P(ProjectionJacobianTest, EqualsAutomaticDifferentiationOfTheCostFunctor) {
  const Case tc = GetParam();
  Camera cam = test::range_camera_at("cam", Vector3d(3, -1, 1.5), Vector3d(0.5, 64, 7.5));
  cam.intr.sx = 1.0007;
  cam.intr.u0_px = 652.3, cam.intr.v0_px = 391.8;
  if (tc.distorted) cam.intr.dist = {-3.4e-4, 2.1e-6, -1.3e-8, 4e-5, -6e-5, 2e-4, -1.5e-4};
  BundleParameterBlocks b = BundleParameterBlocks::from_camera(cam, 0.012);
  const Vector3d w = tc.rotation_rad * Vector3d(0.3, -0.8, 0.5).normalized();
  b.pose[0] = w.x(), b.pose[1] = w.y(), b.pose[2] = w.z();
  b.R0 = Eigen::AngleAxisd(-tc.rotation_rad, Vector3d(0.3, -0.8, 0.5).normalized()).toRotationMatrix() *
         cam.pose.R;

  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  int checked = 0;
  for (int n = 0; n < 200; ++n) {
    const Vector3d X(0.5 + 4 * U(rng), 64 + 4 * U(rng), 7.5 + 3 * U(rng));
    const Vector3d offset(0.1 * U(rng), 0.1 * U(rng), 0.1 * U(rng));
    const Vector3d vel(3 * U(rng), 3 * U(rng), 5 * U(rng));
    AutoDiffCost ad(new ReprojectionResidual{offset, vel, Vector2d::Zero(), Eigen::Matrix2d::Identity(), b.R0,
                                             cam.intr.dx_mm, cam.intr.dy_mm});
    Eigen::Matrix<double, 2, kIntrinsicsBlockSize, Eigen::RowMajor> j0;
    Eigen::Matrix<double, 2, kDistortionBlockSize, Eigen::RowMajor> j1;
    Eigen::Matrix<double, 2, kPoseBlockSize, Eigen::RowMajor> j2;
    Eigen::Matrix<double, 2, kClockBlockSize> j3;
    Eigen::Matrix<double, 2, 3, Eigen::RowMajor> j4;
    const double* params[5] = {b.intr, b.dist, b.pose, b.clock, X.data()};
    double* jac[5] = {j0.data(), j1.data(), j2.data(), j3.data(), j4.data()};
    double ref_uv[2];
    const bool ad_ok = ad.Evaluate(params, ref_uv, jac);

    Vector2d uv;
    ProjectionJacobian pj;
    const bool ok = project_with_jacobian(b.intr, b.dist, b.pose, b.clock[0], b.R0, cam.intr.dx_mm,
                                          cam.intr.dy_mm, X + offset, vel, &uv, &pj);
    ASSERT_EQ(ok, ad_ok);
    if (!ok) continue;
    ++checked;
    EXPECT_NEAR(uv.x(), ref_uv[0], 1e-9);
    EXPECT_NEAR(uv.y(), ref_uv[1], 1e-9);
    // The pixel through vision's own projection of the same camera.
    Vector2d via_vision;
    ASSERT_TRUE(project(b.to_camera(cam), X + offset - vel * b.clock[0], &via_vision));
    EXPECT_NEAR((uv - via_vision).norm(), 0, 1e-6);

    Eigen::Matrix<double, 2, kBundleParameterCount> ref;
    ref << j0, j1, j2, j3;
    for (int c = 0; c < kBundleParameterCount; ++c) {
      const double scale = std::max(1e-12, ref.col(c).norm());
      EXPECT_LT((pj.camera.col(c) - ref.col(c)).norm() / scale, 1e-9)
          << parameter_name(parameter_at(c)) << " at point " << n << "\nanalytic "
          << pj.camera.col(c).transpose() << "\nautodiff " << ref.col(c).transpose();
    }
    const Eigen::Matrix<double, 2, 3> refX = j4;
    EXPECT_LT((pj.world - refX).norm() / refX.norm(), 1e-9) << "world point at point " << n;
  }
  EXPECT_GT(checked, 190);
}

INSTANTIATE_TEST_SUITE_P(Rotations, ProjectionJacobianTest,
                         ::testing::Values(Case{0.0, false}, Case{0.0, true}, Case{3e-5, true},
                                           Case{2e-3, true}, Case{0.4, true}));

// The per-camera bundle's cost function against autodiff of its functor, block by block, with a
// full whitening matrix.
TEST(ProjectionJacobian, BundleCostFunctionEqualsAutomaticDifferentiation) {
  Camera cam = test::range_camera_at("cam", Vector3d(-2, 1, 1.5), Vector3d(0.5, 64, 7.5));
  cam.intr.dist = {-3.4e-4, 2.1e-6, -1.3e-8, 4e-5, -6e-5, 2e-4, -1.5e-4};
  BundleParameterBlocks b = BundleParameterBlocks::from_camera(cam, -0.02);
  b.pose[0] = 1e-3, b.pose[1] = -2e-3, b.pose[2] = 5e-4;
  Eigen::Matrix2d W;
  W << 0.8, 0.1, -0.3, 1.2;
  const ReprojectionResidual functor{
      Vector3d(1.0, 63.0, 6.0), Vector3d(0.5, -1, 4), Vector2d(700, 350), W, b.R0,
      cam.intr.dx_mm,           cam.intr.dy_mm};
  ceres::AutoDiffCostFunction<ReprojectionResidual, 2, kIntrinsicsBlockSize, kDistortionBlockSize,
                              kPoseBlockSize, kClockBlockSize>
      ad(new ReprojectionResidual(functor));
  const ReprojectionCostFunction analytic(functor);
  const double* params[4] = {b.intr, b.dist, b.pose, b.clock};
  double r_ad[2], r_an[2];
  std::vector<double> j_ad(2 * kBundleParameterCount), j_an(2 * kBundleParameterCount);
  double* jad[4] = {j_ad.data(), j_ad.data() + 8, j_ad.data() + 22, j_ad.data() + 34};
  double* jan[4] = {j_an.data(), j_an.data() + 8, j_an.data() + 22, j_an.data() + 34};
  ASSERT_TRUE(ad.Evaluate(params, r_ad, jad));
  ASSERT_TRUE(analytic.Evaluate(params, r_an, jan));
  EXPECT_NEAR(r_an[0], r_ad[0], 1e-9);
  EXPECT_NEAR(r_an[1], r_ad[1], 1e-9);
  for (std::size_t k = 0; k < j_ad.size(); ++k)
    EXPECT_NEAR(j_an[k], j_ad[k], 1e-9 * std::max(1.0, std::abs(j_ad[k]))) << "entry " << k;
}

TEST(ProjectionJacobian, BehindTheCameraIsRefused) {
  const Camera cam = test::range_camera_at("cam", Vector3d(0, 0, 1.5), Vector3d(0.5, 64, 7.5));
  const BundleParameterBlocks b = BundleParameterBlocks::from_camera(cam);
  Vector2d uv;
  ProjectionJacobian pj;
  EXPECT_FALSE(project_with_jacobian(b.intr, b.dist, b.pose, 0, b.R0, cam.intr.dx_mm, cam.intr.dy_mm,
                                     Vector3d(0, -50, 1.5), Vector3d::Zero(), &uv, &pj));
  EXPECT_TRUE(project_with_jacobian(b.intr, b.dist, b.pose, 0, b.R0, cam.intr.dx_mm, cam.intr.dy_mm,
                                    Vector3d(0.5, 64, 7.5), Vector3d::Zero(), &uv, nullptr));
  EXPECT_NEAR(uv.x(), cam.intr.u0_px, 1e-6);
}

}  // namespace
}  // namespace rangecal
