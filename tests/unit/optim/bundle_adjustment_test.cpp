// Bundle adjustment (optim/bundle/bundle_adjustment): truth recovery on noise-free narrow-field points,
// σ calibration and efficiency by Monte Carlo against a Cramér–Rao bound computed here from
// numeric derivatives of vision's project() (not from the code under test), outliers, priors,
// warnings and degenerate input.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <random>
#include <string>

#include "config/error.hpp"
#include "optim/bundle/bundle_adjustment.hpp"
#include "support/bundle_synthetic.hpp"

namespace rangecal {
namespace {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::VectorXd;
using test::narrow_fov_camera;
using test::synthetic_points;

std::vector<BundleObservation> to_obs(const test::SyntheticPoints& s, double world_sd = 0) {
  std::vector<BundleObservation> o(s.world.size());
  for (std::size_t i = 0; i < o.size(); ++i) {
    o[i].world = s.world[i];
    o[i].pixel = s.pixel[i];
    o[i].world_cov = Matrix3d::Identity() * world_sd * world_sd;
  }
  return o;
}

Matrix3d small_rotation(const Vector3d& w) {
  return w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Matrix3d::Identity();
}

/// The truth moved: f +2 %, k1 → 0, rotation by ~5 mrad, centre by ~0.5 m.
Camera perturbed(const Camera& truth) {
  Camera c = truth;
  c.intr.f_mm *= 1.02;
  c.intr.dist.k1 = 0;
  const Vector3d C = truth.pose.center() + Vector3d(0.3, -0.2, 0.35);
  c.pose.R = small_rotation(Vector3d(0.004, -0.003, 0.002)) * truth.pose.R;
  c.pose.T = -c.pose.R * C;
  return c;
}

/// Rotation error as the angle-axis vector of R_truth·R̂ᵀ (the covariance's w about R̂).
Vector3d rotation_error(const Matrix3d& R_hat, const Matrix3d& R_truth) {
  const Eigen::AngleAxisd aa(R_truth * R_hat.transpose());
  return aa.angle() * aa.axis();
}

TEST(BundleAdjustment, NoiseFreeRecoversTruthFromPerturbedStart) {
  const Camera truth = narrow_fov_camera();
  const auto pts = synthetic_points(truth, 60, 17);
  const auto r = bundle_adjust(perturbed(truth), to_obs(pts));
  const Camera& c = r.calibration.camera;
  EXPECT_LT(std::abs(c.intr.f_mm / truth.intr.f_mm - 1), 1e-6);
  EXPECT_LT((c.pose.center() - truth.pose.center()).norm(), 1e-6);
  EXPECT_LT((c.pose.T - truth.pose.T).norm(), 1e-6);
  EXPECT_LT(rotation_error(c.pose.R, truth.pose.R).norm(), 1e-9);
  EXPECT_NEAR(c.intr.dist.k1, truth.intr.dist.k1, 1e-10);
  EXPECT_LT(r.calibration.reprojection.rms_px, 1e-6);
  EXPECT_TRUE(r.calibration.rejected.empty());
  EXPECT_EQ(parameter_names(r.calibration.parameters),
            (std::vector<std::string>{"f", "k1", "wx", "wy", "wz", "CE", "CN", "CU"}));
  EXPECT_EQ(r.calibration.method, "bundle");
}

TEST(BundleAdjustment, NoiseFreeRicherModelRecoversTruth) {
  // Wider depth range and tangential/second radial terms: f, k1, k2, p1, p2 and pose.
  Camera truth = narrow_fov_camera(3e-5);
  truth.intr.dist.k2 = -4e-8;
  truth.intr.dist.p1 = 2e-5;
  truth.intr.dist.p2 = -1e-5;
  const auto pts = synthetic_points(truth, 150, 23, 40, 90);
  BundleOptions o;
  o.free = {"f", "k1", "k2", "p1", "p2", "pose"};
  Camera start = perturbed(truth);
  start.intr.dist = Distortion{};
  const auto r = bundle_adjust(start, to_obs(pts), o);
  const Camera& c = r.calibration.camera;
  EXPECT_LT(std::abs(c.intr.f_mm / truth.intr.f_mm - 1), 1e-6);
  EXPECT_LT((c.pose.center() - truth.pose.center()).norm(), 1e-6);
  EXPECT_NEAR(c.intr.dist.p1, truth.intr.dist.p1, 1e-9);
  EXPECT_LT(r.calibration.reprojection.max_px, 1e-6);
}

// ------------------------------------------------------------------------------------------
// Cramér–Rao bound, computed independently: numeric central differences of vision::project()
// for the parameters (f, k1, wx, wy, wz, CE, CN, CU) with R = exp([w]×)·R_truth (Eigen's
// AngleAxis), and of the world point; effective covariance σ²I + J_X Σ J_Xᵀ; Fisher = Σ JᵀC⁻¹J.
Vector2d project_params(const Camera& truth, const VectorXd& th, const Vector3d& X) {
  Camera c = truth;
  c.intr.f_mm = th[0];
  c.intr.dist.k1 = th[1];
  c.pose.R = small_rotation(th.segment<3>(2)) * truth.pose.R;
  c.pose.T = -c.pose.R * th.segment<3>(5);
  Vector2d uv;
  project(c, X, &uv);
  return uv;
}

MatrixXd cramer_rao(const Camera& truth, const std::vector<Vector3d>& world, double sigma_px,
                    double world_sd) {
  VectorXd th(8);
  th << truth.intr.f_mm, truth.intr.dist.k1, 0, 0, 0, truth.pose.center();
  const double steps[8] = {1e-4, 1e-9, 1e-7, 1e-7, 1e-7, 1e-4, 1e-4, 1e-4};
  MatrixXd F = MatrixXd::Zero(8, 8);
  for (const auto& X : world) {
    Eigen::Matrix<double, 2, 8> J;
    for (int k = 0; k < 8; ++k) {
      VectorXd a = th, b = th;
      a[k] += steps[k], b[k] -= steps[k];
      J.col(k) = (project_params(truth, a, X) - project_params(truth, b, X)) / (2 * steps[k]);
    }
    Eigen::Matrix<double, 2, 3> JX;
    for (int k = 0; k < 3; ++k) {
      Vector3d a = X, b = X;
      a[k] += 1e-4, b[k] -= 1e-4;
      JX.col(k) = (project_params(truth, th, a) - project_params(truth, th, b)) / 2e-4;
    }
    const Eigen::Matrix2d C =
        sigma_px * sigma_px * Eigen::Matrix2d::Identity() + world_sd * world_sd * JX * JX.transpose();
    F += J.transpose() * C.inverse() * J;
  }
  return F.inverse();
}

TEST(BundleAdjustment, MonteCarloSigmasAreCalibratedAndNearCramerRao) {
  // Pixel sd 0.1 px and world sd 1 cm per axis (≈ 1 px at 64 m), 100 runs, fixed seed.
  const Camera truth = narrow_fov_camera();
  const double sp = 0.1, sw = 0.01;
  const auto base = synthetic_points(truth, 60, 5);
  const MatrixXd crb = cramer_rao(truth, base.world, sp, sw);
  const std::vector<std::string> names = {"f", "k1", "wx", "wy", "wz", "CE", "CN", "CU"};
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> N01;  // the noise only needs to be Gaussian, not reproducible
  const int runs = 100;
  VectorXd z2 = VectorXd::Zero(8), mean_sigma = VectorXd::Zero(8);
  double mean_vf = 0;
  for (int run = 0; run < runs; ++run) {
    auto obs = to_obs(base, sw);
    for (auto& o : obs) {
      o.world += sw * Vector3d(N01(rng), N01(rng), N01(rng));
      o.pixel += sp * Vector2d(N01(rng), N01(rng));
    }
    BundleOptions opt;
    opt.pixel_sigma_px = sp;
    const auto r = bundle_adjust(perturbed(truth), obs, opt);
    const auto& cal = r.calibration;
    ASSERT_EQ(parameter_names(cal.parameters), names);
    const Camera& c = cal.camera;
    VectorXd err(8);
    err << c.intr.f_mm - truth.intr.f_mm, c.intr.dist.k1 - truth.intr.dist.k1,
        -rotation_error(c.pose.R, truth.pose.R), c.pose.center() - truth.pose.center();
    for (int k = 0; k < 8; ++k) {
      const double s = cal.sigma(*parameter_from_name(names[k]));
      z2[k] += (err[k] / s) * (err[k] / s) / runs;
      mean_sigma[k] += s / runs;
    }
    mean_vf += r.variance_factor / runs;
  }
  std::printf("variance factor mean %.3f\n", mean_vf);
  for (int k = 0; k < 8; ++k) {
    const double ratio = mean_sigma[k] / std::sqrt(crb(k, k));
    std::printf("%-3s mean (err/σ)² %.3f   σ %.4g   σ/CRB %.3f\n", names[k].c_str(), z2[k], mean_sigma[k],
                ratio);
    EXPECT_GE(z2[k], 0.6) << names[k];
    EXPECT_LE(z2[k], 1.6) << names[k];
    EXPECT_LE(ratio, 1.5) << names[k];
    EXPECT_GE(ratio, 1 / 1.5) << names[k];
  }
  EXPECT_NEAR(mean_vf, 1.0, 0.1);
}

TEST(BundleAdjustment, GrossOutliersAreListedAndDropped) {
  const Camera truth = narrow_fov_camera();
  const auto pts = synthetic_points(truth, 80, 9);
  auto obs = to_obs(pts, 0.01);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> N01;
  for (auto& o : obs) o.pixel += 0.1 * Vector2d(N01(rng), N01(rng));
  const std::vector<std::size_t> bad = {3, 40, 77};
  obs[3].pixel.x() += 25;
  obs[40].pixel.y() -= 18;
  obs[77].pixel += Vector2d(12, 12);
  BundleOptions opt;
  const auto r = bundle_adjust(perturbed(truth), obs, opt);
  EXPECT_EQ(r.calibration.rejected, bad);
  EXPECT_EQ(r.calibration.reprojection.n_rejected, 3);
  for (std::size_t i = 0; i < obs.size(); ++i) EXPECT_EQ(r.outlier[i], i == 3 || i == 40 || i == 77) << i;
  EXPECT_LT(std::abs(r.calibration.camera.intr.f_mm - truth.intr.f_mm),
            4 * r.calibration.sigma(CameraParameter::f));
  EXPECT_GT(r.whitened_norm[3], 10.0);
}

TEST(BundleAdjustment, PriorsBoundTheSigmas) {
  const Camera truth = narrow_fov_camera();
  const auto pts = synthetic_points(truth, 60, 31);
  BundleOptions o;
  o.free = {"f", "u0", "v0", "k1", "pose"};
  o.priors.use_principal_point = true;
  o.priors.principal_point_px = Vector2d(truth.intr.u0_px, truth.intr.v0_px);
  o.priors.principal_point_sigma_px = 2.0;
  o.priors.use_center = true;
  o.priors.center_enu_m = truth.pose.center();
  o.priors.center_sigma_m = Vector3d::Constant(0.002);
  const auto r = bundle_adjust(perturbed(truth), to_obs(pts, 0.01), o);
  const auto& cal = r.calibration;
  EXPECT_LE(cal.sigma(CameraParameter::u0), 2.0);
  EXPECT_LE(cal.sigma(CameraParameter::v0), 2.0);
  EXPECT_LE(cal.center_sigma_m().maxCoeff(), 0.002);
  EXPECT_GT(cal.sigma(CameraParameter::u0), 0.0);
  // Noise free with the priors at the truth: the truth is still the solution.
  EXPECT_LT((cal.camera.pose.center() - truth.pose.center()).norm(), 1e-6);
  EXPECT_NEAR(cal.camera.intr.u0_px, truth.intr.u0_px, 1e-5);
}

TEST(BundleAdjustment, PrincipalPointFreeWithNarrowLensWarnsNamingThePair) {
  // docs/optimisation.md: with a 10° field u0 and the rotation about the camera's y axis are nearly the same
  // thing; without a prior the bundle must say so.
  const Camera truth = narrow_fov_camera();
  const auto pts = synthetic_points(truth, 60, 41);
  auto obs = to_obs(pts, 0.01);
  BundleOptions o;
  o.free = {"f", "u0", "v0", "k1", "pose"};
  const auto r = bundle_adjust(perturbed(truth), obs, o);
  bool found = false;
  for (const auto& w : r.calibration.warnings)
    if (w.find("u0 and wy") != std::string::npos) found = true;
  EXPECT_TRUE(found);
  EXPECT_GT(std::abs(r.calibration.correlation(CameraParameter::u0, CameraParameter::wy)), 0.99);
  // A principal-point prior (σ 2 px) separates them: no u0/wy warning any more.
  o.priors.use_principal_point = true;
  o.priors.principal_point_px = Vector2d(640, 400);
  o.priors.principal_point_sigma_px = 2.0;
  const auto d = bundle_adjust(perturbed(truth), obs, o);
  for (const auto& w : d.calibration.warnings) EXPECT_EQ(w.find("u0 and wy"), std::string::npos) << w;
  EXPECT_LT(std::abs(d.calibration.correlation(CameraParameter::u0, CameraParameter::wy)), 0.99);
}

TEST(BundleAdjustment, RankDeficientCovarianceIsReportedNotACrash) {
  // Every point on the image row through the principal point (yd = 0): a2 (Δy = a2·yd) has no
  // effect on any pixel.
  const Camera truth = narrow_fov_camera();
  std::vector<BundleObservation> obs;
  for (int i = 0; i < 30; ++i) {
    const Vector2d uv(40 + 40 * i, truth.intr.v0_px);
    const Vector2d su = pixel_to_undistorted_sensor(truth.intr, uv);
    const double depth = 50 + (i * 7) % 30;
    const Vector3d xc(su.x() / truth.intr.f_mm * depth, su.y() / truth.intr.f_mm * depth, depth);
    BundleObservation o;
    o.world = truth.pose.R.transpose() * (xc - truth.pose.T);
    project(truth, o.world, &o.pixel);
    obs.push_back(o);
  }
  BundleOptions o;
  o.free = {"f", "k1", "a2"};
  const auto r = bundle_adjust(truth, obs, o);
  EXPECT_TRUE(r.rank_deficient);
  EXPECT_EQ(r.calibration.covariance.size(), 0);
  bool named = false;
  for (const auto& w : r.calibration.warnings)
    if (w.find("rank-deficient") != std::string::npos && w.find("a2") != std::string::npos) named = true;
  EXPECT_TRUE(named);
}

void expect_calibration_error(const Camera& cam, const std::vector<BundleObservation>& obs,
                              const BundleOptions& o, const std::string& needle) {
  try {
    bundle_adjust(cam, obs, o);
    FAIL() << "expected a calibration error containing '" << needle << "'";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::calibration) << e.what();
    EXPECT_EQ(e.exit_code(), 4);
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(BundleAdjustment, AllPointsOnOneVerticalLineIsDegenerate) {
  const Camera truth = narrow_fov_camera();
  std::vector<BundleObservation> obs;
  for (int i = 0; i < 20; ++i) {
    BundleObservation o;
    o.world = Vector3d(40, 48, 5 + 1.5 * i);  // one vertical ascent
    project(truth, o.world, &o.pixel);
    obs.push_back(o);
  }
  expect_calibration_error(perturbed(truth), obs, {}, "one line");
}

TEST(BundleAdjustment, FewerPointsThanUnknownsIsDegenerate) {
  const Camera truth = narrow_fov_camera();
  const auto obs = to_obs(synthetic_points(truth, 3, 2));
  expect_calibration_error(perturbed(truth), obs, {}, "fewer observations than unknowns");
}

TEST(BundleAdjustment, NaNInputNamesTheObservation) {
  const Camera truth = narrow_fov_camera();
  auto obs = to_obs(synthetic_points(truth, 20, 2));
  obs[4].pixel.y() = std::nan("");
  expect_calibration_error(perturbed(truth), obs, {}, "observation 5.pixel");
  obs = to_obs(synthetic_points(truth, 20, 2));
  obs[7].world.z() = std::nan("");
  expect_calibration_error(perturbed(truth), obs, {}, "observation 8.world");
}

TEST(BundleAdjustment, PointsBehindTheStartAndUnknownNamesAreErrors) {
  const Camera truth = narrow_fov_camera();
  const auto obs = to_obs(synthetic_points(truth, 20, 2));
  Camera flipped = truth;
  flipped.pose.R = Eigen::AngleAxisd(M_PI, Vector3d::UnitX()).toRotationMatrix() * truth.pose.R;
  flipped.pose.T = -flipped.pose.R * truth.pose.center();
  expect_calibration_error(flipped, obs, {}, "behind the initial camera");
  BundleOptions o;
  o.free = {"f", "focal"};
  try {
    bundle_adjust(truth, obs, o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("focal"), std::string::npos);
  }
}

TEST(BundleAdjustment, PixelJacobianMatchesFiniteDifferences) {
  const Camera truth = narrow_fov_camera(5e-5);
  const Vector3d X = synthetic_points(truth, 1, 8).world[0];
  const auto J = pixel_jacobian_wrt_world(truth, X);
  for (int k = 0; k < 3; ++k) {
    Vector3d a = X, b = X;
    a[k] += 1e-4, b[k] -= 1e-4;
    Vector2d pa, pb;
    project(truth, a, &pa);
    project(truth, b, &pb);
    EXPECT_NEAR(J(0, k), (pa - pb).x() / 2e-4, 1e-5 * std::abs(J(0, k)) + 1e-6);
    EXPECT_NEAR(J(1, k), (pa - pb).y() / 2e-4, 1e-5 * std::abs(J(1, k)) + 1e-6);
  }
}

}  // namespace
}  // namespace rangecal
