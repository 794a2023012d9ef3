// The bundle's weighting (optim/bundle/whitening.hpp): ∂pixel/∂world against central differences of
// vision's project(); W·C·Wᵀ = I with C = σ²·I + J_X·Σ_X·J_Xᵀ formed from those differences; W lower
// triangular (W = L⁻¹); and each observation's own σ used when it gives one.
#include "optim/bundle/whitening.hpp"

#include <gtest/gtest.h>

#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

using Eigen::Matrix2d;
using Eigen::Vector2d;
using Eigen::Vector3d;

Camera distorted_camera() {
  Camera cam = test::range_camera_at("cam", Vector3d(0, 0, 1.5), Vector3d(0.5, 64, 7.5));
  cam.intr.dist = {-3.4e-4, 2.1e-6, 0, 4e-5, -6e-5, 2e-4, -1.5e-4};
  return cam;
}

Eigen::Matrix<double, 2, 3> finite_difference_jacobian(const Camera& cam, const Vector3d& X) {
  Eigen::Matrix<double, 2, 3> J;
  const double h = 1e-4;  // m
  for (int a = 0; a < 3; ++a) {
    Vector2d plus, minus;
    EXPECT_TRUE(project(cam, X + h * Vector3d::Unit(a), &plus));
    EXPECT_TRUE(project(cam, X - h * Vector3d::Unit(a), &minus));
    J.col(a) = (plus - minus) / (2 * h);
  }
  return J;
}

TEST(Whitening, PixelJacobianMatchesFiniteDifferences) {
  const Camera cam = distorted_camera();
  for (const Vector3d& X : {Vector3d(0.5, 64, 7.5), Vector3d(-3, 60, 4), Vector3d(4, 68, 11)}) {
    const Eigen::Matrix<double, 2, 3> J = pixel_jacobian_wrt_world(cam, X);
    const Eigen::Matrix<double, 2, 3> ref = finite_difference_jacobian(cam, X);
    // ≈ 135 mm / 20 µm / 64 m ≈ 105 px/m.
    EXPECT_GT(J.norm(), 100);
    EXPECT_LT((J - ref).norm(), 1e-6 * ref.norm()) << "at " << X.transpose();
  }
}

TEST(Whitening, WhitensTheEffectivePixelCovariance) {
  const Camera cam = distorted_camera();
  BundleObservation o;
  o.world = Vector3d(-3, 60, 4);
  o.world_cov << 1e-4, 2e-5, -1e-5, 2e-5, 2e-4, 3e-5, -1e-5, 3e-5, 4e-4;  // a PPK-like full 3 × 3 (m²)
  const double sigma = 0.1;
  const Matrix2d W = whitening_matrix(cam, o, sigma);
  const Eigen::Matrix<double, 2, 3> JX = finite_difference_jacobian(cam, o.world);
  const Matrix2d C = sigma * sigma * Matrix2d::Identity() + JX * o.world_cov * JX.transpose();
  EXPECT_LT((W * C * W.transpose() - Matrix2d::Identity()).norm(), 1e-6);
  EXPECT_EQ(W(0, 1), 0.0);  // L⁻¹ of a Cholesky factor
  // Without world noise W is I/σ.
  o.world_cov.setZero();
  EXPECT_LT((whitening_matrix(cam, o, sigma) - Matrix2d::Identity() / sigma).norm(), 1e-9);
}

TEST(Whitening, EachObservationsOwnSigmaElseTheDefault) {
  const Camera cam = distorted_camera();
  std::vector<BundleObservation> obs(2);
  obs[0].world = obs[1].world = Vector3d(0.5, 64, 7.5);
  obs[0].pixel_sigma_px = 0.5;
  obs[1].pixel_sigma_px = 0;  // the default
  const std::vector<Matrix2d> W = whitening_matrices(cam, obs, 0.25);
  ASSERT_EQ(W.size(), 2u);
  EXPECT_LT((W[0] - 2 * Matrix2d::Identity()).norm(), 1e-12);
  EXPECT_LT((W[1] - 4 * Matrix2d::Identity()).norm(), 1e-12);
}

}  // namespace
}  // namespace rangecal
