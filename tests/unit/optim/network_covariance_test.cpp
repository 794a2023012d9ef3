// The network's covariance (optim/network/network_covariance.hpp) against the dense normal equations
// of every camera's free parameters and every point, formed here from Ceres' automatic
// differentiation of the image residual's functor (optim/bundle/reprojection_cost.hpp) and the
// points' prior rows, and inverted whole: the Schur complement's S⁻¹ is the cameras' block of that
// inverse, each point's covariance its point block, and the degrees of freedom are the same. The
// scene has no single-view point (whose posterior is a Woodbury update, not a block of this inverse).
#include "optim/network/network_covariance.hpp"

#include <ceres/autodiff_cost_function.h>
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "support/synthetic_network.hpp"

namespace rangecal {
namespace {

using Eigen::MatrixXd;
using AutoDiffImageCost =
    ceres::AutoDiffCostFunction<ReprojectionResidual, 2, kIntrinsicsBlockSize, kDistortionBlockSize,
                                kPoseBlockSize, kClockBlockSize, 3>;

using Network = test::NetworkScene;

/// In place: the layout points into `n->data`.
void build(Network* network) {
  Network& n = *network;
  n.data = test::synthetic_network(3, 40, 21);
  for (std::size_t i = 0; i < n.data.observations.size(); i += 2) {  // the lamp between frames
    n.data.observations[i].offset_m = Eigen::Vector3d(0.01, -0.005, 0.02);
    n.data.observations[i].velocity = Eigen::Vector3d(0.5, 0, 3);
  }
  test::lay_out_network(&n, 0.003);
}

/// The whitened Jacobian of every image residual and point prior over [cameras' free columns, points].
MatrixXd dense_jacobian(const Network& n) {
  const NetworkLayout& l = n.layout;
  const int ncam = l.n_camera_parameters;
  const auto np = static_cast<int>(n.data.points.size());
  MatrixXd J = MatrixXd::Zero(2 * static_cast<int>(n.data.observations.size()) + 3 * np, ncam + 3 * np);
  int row = 0;
  for (std::size_t i = 0; i < n.data.observations.size(); ++i) {
    const NetworkObservation& o = n.data.observations[i];
    const BundleParameterBlocks& cb = n.blocks.cameras[o.camera];
    const Camera& base = l.starts[o.camera];
    AutoDiffImageCost ad(new ReprojectionResidual{o.offset_m, o.velocity, o.pixel,
                                                  Eigen::Matrix2d::Identity() / l.pixel_sigma(i), cb.R0,
                                                  base.intr.dx_mm, base.intr.dy_mm});
    Eigen::Matrix<double, 2, kIntrinsicsBlockSize, Eigen::RowMajor> j0;
    Eigen::Matrix<double, 2, kDistortionBlockSize, Eigen::RowMajor> j1;
    Eigen::Matrix<double, 2, kPoseBlockSize, Eigen::RowMajor> j2;
    Eigen::Matrix<double, 2, kClockBlockSize> j3;
    Eigen::Matrix<double, 2, 3, Eigen::RowMajor> j4;
    const double* params[5] = {cb.intr, cb.dist, cb.pose, cb.clock, n.blocks.points[o.point].data()};
    double* jac[5] = {j0.data(), j1.data(), j2.data(), j3.data(), j4.data()};
    double r[2];
    EXPECT_TRUE(ad.Evaluate(params, r, jac));
    Eigen::Matrix<double, 2, kBundleParameterCount> all;
    all << j0, j1, j2, j3;
    const std::vector<CameraParameter>& free = l.free[o.camera];
    for (std::size_t m = 0; m < free.size(); ++m)
      J.block(row, l.offset[o.camera] + static_cast<int>(m), 2, 1) = all.col(index_of(free[m]));
    J.block(row, ncam + 3 * static_cast<int>(o.point), 2, 3) = j4;
    row += 2;
  }
  for (int k = 0; k < np; ++k, row += 3)
    J.block(row, ncam + 3 * k, 3, 3) = l.prior_whiten[static_cast<std::size_t>(k)];
  return J;
}

TEST(NetworkCovariance, EqualsTheDenseInverseOfTheWholeNormalMatrix) {
  Network n;
  build(&n);
  const NetworkLayout& l = n.layout;
  ASSERT_FALSE(l.setups[0].center_prior);
  ASSERT_FALSE(l.setups[0].principal_point_prior);
  int single_view = 0, multi_view = 0;
  for (std::size_t k = 0; k < n.data.points.size(); ++k)
    (n.selection.single_view[k] ? single_view : multi_view)++;
  // Every point of this scene is seen by two cameras or more: the oracle takes each point as a
  // parameter under its prior, which a single-view point is not (its one ray is weighted by the
  // effective variance instead, network_covariance.hpp), so a scene with one would not compare.
  ASSERT_EQ(single_view, 0);
  ASSERT_GT(multi_view, 10);

  const NetworkCovariance cov = network_covariance(l, n.blocks, n.selection, 64, 3, 1e-14);
  ASSERT_FALSE(cov.rank_deficient);
  const MatrixXd J = dense_jacobian(n);
  const MatrixXd full = (J.transpose() * J).fullPivLu().inverse();
  const int ncam = l.n_camera_parameters;
  ASSERT_EQ(cov.joint.rows(), ncam);
  for (int a = 0; a < ncam; ++a)
    for (int b = 0; b < ncam; ++b)
      EXPECT_NEAR(cov.joint(a, b), full(a, b), 1e-6 * std::sqrt(full(a, a) * full(b, b))) << a << ", " << b;
  for (std::size_t k = 0; k < n.data.points.size(); ++k) {
    const Eigen::Matrix3d expected =
        full.block(ncam + 3 * static_cast<int>(k), ncam + 3 * static_cast<int>(k), 3, 3);
    EXPECT_LT((cov.point_cov[k] - expected).norm(), 1e-6 * expected.norm()) << "point " << k;
  }
  EXPECT_EQ(cov.residuals - cov.parameters, J.rows() - J.cols());
}

TEST(NetworkCovariance, ACameraTheDataDoNotDetermineIsReportedByName) {
  Network n;
  build(&n);
  // Nothing left of cam2: its parameters are in no residual.
  for (std::size_t i = 0; i < n.data.observations.size(); ++i)
    if (n.data.observations[i].camera == 1) n.selection.observation[i] = 0;
  refresh_single_view(n.layout, n.blocks, &n.selection);
  const NetworkCovariance cov = network_covariance(n.layout, n.blocks, n.selection, 64, 3, 1e-14);
  EXPECT_TRUE(cov.rank_deficient);
  EXPECT_EQ(cov.joint.size(), 0);
  ASSERT_EQ(cov.warnings.size(), 1u);
  EXPECT_NE(cov.warnings[0].find("do not depend on cam2 f, cam2 k1, cam2 wx"), std::string::npos)
      << cov.warnings[0];
  // As each camera's code (optim/bundle/calibration_warning.hpp): cam2's names its own free
  // parameters, every one; cam1's and cam3's name none of theirs.
  for (std::size_t c = 0; c < 3; ++c) {
    const std::vector<CalibrationWarning> codes =
        rank_deficiency_warnings(cov.warnings, cov.named, n.layout.free[c], n.data.cameras[c].initial.id,
                                 static_cast<Eigen::Index>(n.layout.offset[c]));
    ASSERT_EQ(codes.size(), 1u);
    EXPECT_EQ(codes[0].kind, CalibrationWarningKind::rank_deficient);
    EXPECT_EQ(codes[0].parameters, c == 1 ? n.layout.free[c] : std::vector<CameraParameter>{}) << c;
  }
}

}  // namespace
}  // namespace rangecal
