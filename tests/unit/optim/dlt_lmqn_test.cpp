// dlt_lmqn (optim/methods/dlt_lmqn.hpp) on exact projections of a seed-002-like camera with two gross
// outliers: the outliers are the rejected points, the camera is the truth, and the covariance equals
// (JᵀJ)⁻¹ of the whitened residuals differentiated here by central differences through vision's
// camera_with_parameters and project().
#include "optim/methods/dlt_lmqn.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "optim/bundle/whitening.hpp"
#include "support/bundle_synthetic.hpp"

namespace rangecal {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

TEST(DltLmqn, RejectsTheGrossOutliersAndRecoversTheCamera) {
  const Camera truth = test::narrow_fov_camera(2e-5);
  const test::SyntheticPoints pts = test::synthetic_points(truth, 60, 17);
  std::vector<BundleObservation> obs;
  for (std::size_t i = 0; i < pts.world.size(); ++i) {
    BundleObservation o;
    o.world = pts.world[i];
    o.pixel = pts.pixel[i];
    o.world_cov = Eigen::Matrix3d::Identity() * 1e-6;  // 1 mm
    obs.push_back(o);
  }
  obs[9].pixel += Eigen::Vector2d(40, -30);
  obs[33].pixel += Eigen::Vector2d(-25, 60);
  SensorGeometry sensor;
  sensor.width_px = truth.intr.width_px;
  sensor.height_px = truth.intr.height_px;
  sensor.dx_mm = truth.intr.dx_mm;
  sensor.dy_mm = truth.intr.dy_mm;
  DltLmqnOptions opt;
  opt.fixed_principal_point_px = Eigen::Vector2d(truth.intr.u0_px, truth.intr.v0_px);
  const DltLmqnResult res = dlt_lmqn_calibrate(obs, sensor, opt);

  EXPECT_EQ(res.rejected, (std::vector<std::size_t>{9, 33}));
  EXPECT_EQ(res.used.size(), obs.size() - 2);
  EXPECT_NEAR(res.camera.intr.f_mm, truth.intr.f_mm, 1e-6 * truth.intr.f_mm);
  EXPECT_NEAR(res.camera.intr.dist.k1, truth.intr.dist.k1, 1e-4 * std::abs(truth.intr.dist.k1));
  EXPECT_LT((res.camera.pose.center() - truth.pose.center()).norm(), 1e-5);
  EXPECT_EQ(res.parameters, opt.free);

  // (JᵀJ)⁻¹ of the whitened residuals over the used points, by central differences. The method
  // whitens with weights taken once, at its DLT start (res.start), and keeps them through LM-QN: its
  // covariance is that of the objective it minimised. Weights refreshed at the solution move σ by
  // about 2 % here (the start's f is 135.016 mm against 135), which the 0.2 % below tells apart.
  const std::vector<Eigen::Matrix2d> W = whitening_matrices(res.start, obs, opt.pixel_sigma_px);
  const VectorXd x0 = parameter_values(res.camera, res.parameters);
  const auto residuals = [&](const VectorXd& x) {
    const Camera c = camera_with_parameters(res.camera, res.parameters, x);
    VectorXd r(2 * static_cast<Eigen::Index>(res.used.size()));
    for (std::size_t k = 0; k < res.used.size(); ++k) {
      Eigen::Vector2d uv;
      EXPECT_TRUE(project(c, obs[res.used[k]].world, &uv));
      r.segment<2>(2 * static_cast<Eigen::Index>(k)) = W[res.used[k]] * (uv - obs[res.used[k]].pixel);
    }
    return r;
  };
  MatrixXd J(2 * static_cast<Eigen::Index>(res.used.size()), x0.size());
  for (Eigen::Index j = 0; j < x0.size(); ++j) {
    const double h = 1e-3 * parameter_info(res.parameters[static_cast<std::size_t>(j)]).search_scale;
    VectorXd plus = x0, minus = x0;
    plus[j] += h;
    minus[j] -= h;
    J.col(j) = (residuals(plus) - residuals(minus)) / (2 * h);
  }
  const MatrixXd expected = (J.transpose() * J).fullPivLu().inverse();
  ASSERT_EQ(res.covariance.rows(), x0.size());
  for (Eigen::Index j = 0; j < x0.size(); ++j)
    EXPECT_NEAR(std::sqrt(res.covariance(j, j)), std::sqrt(expected(j, j)), 0.002 * std::sqrt(expected(j, j)))
        << parameter_name(res.parameters[static_cast<std::size_t>(j)]);
}

}  // namespace
}  // namespace rangecal
