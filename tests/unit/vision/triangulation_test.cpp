#include "vision/triangulation/triangulation.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <random>

#include "config/error.hpp"
#include "support/expect_error.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

// Seed 002's cameras: 1280×800, 20 µm pixels, 135 mm lens, k1 ≈ −3.4e−4 mm⁻², ~64 m away.
Camera look_at_camera(const std::string& id, const Eigen::Vector3d& C, const Eigen::Vector3d& target) {
  return test::range_camera_at(id, C, target, -3.4e-4, {640.3, 399.6});
}

const Eigen::Vector3d kAim(0, 0, 20);
const Eigen::Vector3d kPoint(1.3, -2.1, 23.4);  // off the optical axes: distortion matters

std::vector<TriangulationView> two_views(const Eigen::Vector3d& X = kPoint) {
  std::vector<TriangulationView> v(2);
  v[0].camera = look_at_camera("cam1", {-42, -48, 1.5}, kAim);  // 66 m from the point, 84 m baseline
  v[1].camera = look_at_camera("cam2", {42, -46, 1.8}, kAim);
  for (auto& w : v) {
    EXPECT_TRUE(project(w.camera, X, &w.uv_px));
    w.pick_sigma_px = 0.2;
  }
  return v;
}

TEST(Triangulation, NoiseFreeIsExact) {
  const auto views = two_views();
  EXPECT_NEAR((views[0].camera.pose.center() - kPoint).norm(), 66, 3);
  const TriangulationResult r = triangulate_point(views, "pole A1");
  EXPECT_LT((r.point - kPoint).norm(), 1e-6);
  EXPECT_LT(r.rms_px, 1e-6);
  EXPECT_LT((r.linear_point - kPoint).norm(), 1e-6);  // exact rays meet exactly
  EXPECT_GT(r.max_ray_angle_deg, 60);
  EXPECT_LE(r.iterations, 5);
}

TEST(Triangulation, ThreeCamerasNoiseFreeAndNonlinearImprovesOnLinear) {
  auto views = two_views();
  TriangulationView v3;
  v3.camera = look_at_camera("cam3", {5, 60, 3}, kAim);
  ASSERT_TRUE(project(v3.camera, kPoint, &v3.uv_px));
  views.push_back(v3);
  EXPECT_LT((triangulate_point(views).point - kPoint).norm(), 1e-6);
  // With a 1 px error in one pick the nonlinear solution has smaller reprojection error than the
  // linear midpoint (which minimises metric distance to rays, not pixels).
  views[2].uv_px.x() += 1.0;
  const TriangulationResult r = triangulate_point(views);
  double lin_sq = 0;
  for (const auto& v : views) {
    Eigen::Vector2d uv;
    ASSERT_TRUE(project(v.camera, r.linear_point, &uv));
    lin_sq += (uv - v.uv_px).squaredNorm();
  }
  EXPECT_LT(r.rms_px, std::sqrt(lin_sq / 3));
  EXPECT_GT(r.rms_px, 0.1);
  EXPECT_EQ(r.residuals_px.size(), 3u);
}

TEST(Triangulation, PickNoiseCovarianceMatchesMonteCarlo) {
  const auto truth = two_views();
  const TriangulationResult nominal = triangulate_point(truth);
  EXPECT_EQ(nominal.cov_calibration_m2, Eigen::Matrix3d::Zero());
  std::mt19937_64 rng(20261123);
  std::normal_distribution<double> g(0.0, 0.2);
  const int trials = 500;
  std::vector<Eigen::Vector3d> pts;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int t = 0; t < trials; ++t) {
    auto views = truth;
    for (auto& v : views) v.uv_px += Eigen::Vector2d(g(rng), g(rng));
    pts.push_back(triangulate_point(views).point);
    mean += pts.back() / trials;
  }
  Eigen::Matrix3d emp = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) emp += (p - mean) * (p - mean).transpose() / (trials - 1);
  for (int k = 0; k < 3; ++k) {
    const double pred = std::sqrt(nominal.cov_pick_m2(k, k)), got = std::sqrt(emp(k, k));
    EXPECT_NEAR(got / pred, 1.0, 0.15) << "axis " << k << " predicted " << pred << " MC " << got;
    ::testing::Test::RecordProperty("mc_over_predicted_axis" + std::to_string(k), std::to_string(got / pred));
  }
  EXPECT_NEAR(nominal.sigma_m, std::sqrt(nominal.cov_pick_m2.trace()), 1e-15);
  ::testing::Test::RecordProperty("sigma_m", std::to_string(nominal.sigma_m));
  EXPECT_GT(nominal.sigma_m, 1e-3);  // ~mm at 66 m for 0.2 px
  EXPECT_LT(nominal.sigma_m, 1e-2);
}

/// Applies a perturbation in the names' units to a camera (the model the covariance describes).
Camera perturbed(const Camera& c, const std::vector<std::string>& names, const Eigen::VectorXd& d) {
  Camera p = c;
  Eigen::Vector3d w = Eigen::Vector3d::Zero(), dT = Eigen::Vector3d::Zero(), dC = Eigen::Vector3d::Zero();
  bool t_mode = false;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string& n = names[k];
    const double v = d[static_cast<Eigen::Index>(k)];
    if (n == "f") p.intr.f_mm += v;
    if (n == "u0") p.intr.u0_px += v;
    if (n == "v0") p.intr.v0_px += v;
    if (n == "k1") p.intr.dist.k1 += v;
    if (n == "wx") w.x() = v;
    if (n == "wy") w.y() = v;
    if (n == "wz") w.z() = v;
    if (n == "Tx" || n == "Ty" || n == "Tz") t_mode = true;
    if (n == "Tx") dT.x() = v;
    if (n == "Ty") dT.y() = v;
    if (n == "Tz") dT.z() = v;
    if (n == "CE") dC.x() = v;
    if (n == "CN") dC.y() = v;
    if (n == "CU") dC.z() = v;
  }
  const Eigen::Matrix3d Rw = w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix()
                                          : Eigen::Matrix3d::Identity();
  p.pose.R = Rw * c.pose.R;
  if (t_mode) {
    p.pose.T = c.pose.T + dT;
  } else {
    p.pose.T = -p.pose.R * (c.pose.center() + dC);
  }
  return p;
}

Eigen::MatrixXd correlated_covariance(const Eigen::VectorXd& sd, std::mt19937_64& rng) {
  const auto m = sd.size();
  std::normal_distribution<double> g;
  Eigen::MatrixXd B(m, m);
  for (Eigen::Index i = 0; i < m; ++i)
    for (Eigen::Index j = 0; j < m; ++j) B(i, j) = g(rng);
  Eigen::MatrixXd C = B * B.transpose() + static_cast<double>(m) * Eigen::MatrixXd::Identity(m, m);
  const Eigen::VectorXd s = C.diagonal().cwiseSqrt().cwiseInverse();
  C = s.asDiagonal() * C * s.asDiagonal();  // a correlation matrix with sizeable off-diagonals
  return sd.asDiagonal() * C * sd.asDiagonal();
}

void check_calibration_monte_carlo(const std::vector<std::string>& names, const Eigen::VectorXd& sd,
                                   int trials) {
  std::mt19937_64 rng(4242);
  auto truth = two_views();
  for (auto& v : truth) {
    v.calibration.parameters = test::parameters(names);
    v.calibration.covariance = correlated_covariance(sd, rng);
  }
  const TriangulationResult nominal = triangulate_point(truth);
  std::vector<Eigen::MatrixXd> L;
  for (const auto& v : truth) L.push_back(v.calibration.covariance.llt().matrixL());
  std::normal_distribution<double> g;
  std::vector<Eigen::Vector3d> pts;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int t = 0; t < trials; ++t) {
    auto views = truth;  // true pixels, cameras as (wrongly) calibrated
    for (std::size_t i = 0; i < views.size(); ++i) {
      Eigen::VectorXd z(sd.size());
      for (Eigen::Index k = 0; k < z.size(); ++k) z[k] = g(rng);
      views[i].camera = perturbed(truth[i].camera, names, L[i] * z);
    }
    pts.push_back(triangulate_point(views).point);
    mean += pts.back() / trials;
  }
  Eigen::Matrix3d emp = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) emp += (p - mean) * (p - mean).transpose() / (trials - 1);
  for (int k = 0; k < 3; ++k) {
    const double pred = std::sqrt(nominal.cov_calibration_m2(k, k)), got = std::sqrt(emp(k, k));
    EXPECT_NEAR(got / pred, 1.0, 0.20) << "axis " << k << " predicted " << pred << " MC " << got;
    ::testing::Test::RecordProperty("mc_over_predicted_axis" + std::to_string(k), std::to_string(got / pred));
  }
  EXPECT_NEAR(nominal.cov_m2.trace(), nominal.cov_pick_m2.trace() + nominal.cov_calibration_m2.trace(),
              1e-18);
}

TEST(Triangulation, CalibrationCovarianceMatchesMonteCarloCentreForm) {
  // σ: f 0.3 mm, u0 v0 3 px, k1 5e−6 mm⁻², rotation 3e−5 rad (≈ 0.2 px), centre 1–2 cm.
  Eigen::VectorXd sd(10);
  sd << 0.3, 3.0, 3.0, 5e-6, 3e-5, 3e-5, 3e-5, 0.01, 0.015, 0.02;
  check_calibration_monte_carlo({"f", "u0", "v0", "k1", "wx", "wy", "wz", "CE", "CN", "CU"}, sd, 500);
}

TEST(Triangulation, CalibrationCovarianceMatchesMonteCarloTranslationForm) {
  Eigen::VectorXd sd(6);
  sd << 3e-5, 3e-5, 3e-5, 0.01, 0.01, 0.03;
  check_calibration_monte_carlo({"wx", "wy", "wz", "Tx", "Ty", "Tz"}, sd, 400);
}

TEST(Triangulation, ParameterJacobianMatchesFiniteDifferences) {
  const Camera c = two_views()[0].camera;
  const std::vector<std::string> names = {"f",  "sx", "u0", "v0", "k1", "k2", "k3", "p1", "p2",
                                          "a1", "a2", "wx", "wy", "wz", "CE", "CN", "CU"};
  Eigen::Matrix<double, 2, 3> dX;
  const Eigen::MatrixXd J = pixel_jacobian_wrt_parameters(c, test::parameters(names), kPoint, &dX);
  const double steps[17] = {1e-4, 1e-7, 1e-4, 1e-4, 1e-9, 1e-12, 1e-15, 1e-8, 1e-8,
                            1e-7, 1e-7, 1e-7, 1e-7, 1e-7, 1e-4,  1e-4,  1e-4};
  for (std::size_t k = 0; k < names.size(); ++k) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(17);
    Eigen::Vector2d up, dn;
    if (names[k] == "sx" || names[k] == "k2" || names[k] == "k3" || names[k] == "p1" || names[k] == "p2" ||
        names[k] == "a1" || names[k] == "a2") {
      Camera a = c, b = c;  // perturbed() above handles only the common names: do these by hand
      auto bump = [&](Camera& x, double s) {
        if (names[k] == "sx") x.intr.sx += s;
        if (names[k] == "k2") x.intr.dist.k2 += s;
        if (names[k] == "k3") x.intr.dist.k3 += s;
        if (names[k] == "p1") x.intr.dist.p1 += s;
        if (names[k] == "p2") x.intr.dist.p2 += s;
        if (names[k] == "a1") x.intr.dist.a1 += s;
        if (names[k] == "a2") x.intr.dist.a2 += s;
      };
      bump(a, steps[k]);
      bump(b, -steps[k]);
      ASSERT_TRUE(project(a, kPoint, &up));
      ASSERT_TRUE(project(b, kPoint, &dn));
    } else {
      d[static_cast<Eigen::Index>(k)] = steps[k];
      ASSERT_TRUE(project(perturbed(c, names, d), kPoint, &up));
      ASSERT_TRUE(project(perturbed(c, names, -d), kPoint, &dn));
    }
    const Eigen::Vector2d fd = (up - dn) / (2 * steps[k]);
    EXPECT_LT((fd - J.col(static_cast<Eigen::Index>(k))).norm(), 1e-5 * (1 + fd.norm())) << names[k];
  }
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3d h = Eigen::Vector3d::Zero();
    h[a] = 1e-4;
    Eigen::Vector2d up, dn;
    ASSERT_TRUE(project(c, kPoint + h, &up));
    ASSERT_TRUE(project(c, kPoint - h, &dn));
    EXPECT_LT(((up - dn) / 2e-4 - dX.col(a)).norm(), 1e-4);
  }
}

using test::expect_error;

TEST(Triangulation, Errors) {
  auto views = two_views();
  Error e = expect_error([&] { triangulate_point({views[0]}, "pole A3"); });
  EXPECT_EQ(e.kind(), ErrorKind::calibration);
  EXPECT_EQ(e.field(), "pole A3");
  EXPECT_NE(e.reason().find("at least two"), std::string::npos) << e.what();

  // Parallel: cam2 stands 10 m behind cam1 on the same line of sight.
  auto par = views;
  const Eigen::Vector3d C1 = views[0].camera.pose.center();
  par[1].camera = look_at_camera("cam2", C1 - 10 * (kPoint - C1).normalized(), kAim);
  ASSERT_TRUE(project(par[1].camera, kPoint, &par[1].uv_px));
  e = expect_error([&] { triangulate_point(par, "pole A4"); });
  EXPECT_EQ(e.kind(), ErrorKind::calibration);
  EXPECT_NE(e.reason().find("parallel"), std::string::npos) << e.what();

  // Behind: cam2's pick lies on the line through the point, but on the far side of cam2.
  auto behind = views;
  const Eigen::Vector3d C2 = views[1].camera.pose.center();
  behind[1].camera = look_at_camera("cam2", C2, C2 + (C2 - kPoint));
  ASSERT_TRUE(project(behind[1].camera, C2 + (C2 - kPoint), &behind[1].uv_px));
  e = expect_error([&] { triangulate_point(behind, "pole A5"); });
  EXPECT_EQ(e.kind(), ErrorKind::calibration);
  EXPECT_NE(e.reason().find("behind camera cam2"), std::string::npos) << e.what();

  // (An unknown parameter name cannot reach the triangulation: calibration.json's reader refuses
  // it, tests/unit/pipeline/calibration_json_test.cpp.)
  auto bad = views;
  bad[0].calibration.parameters = test::parameters({"f", "u0"});
  bad[0].calibration.covariance = Eigen::Matrix3d::Identity();
  e = expect_error([&] { triangulate_point(bad); });
  EXPECT_EQ(e.kind(), ErrorKind::calibration);

  bad = views;
  bad[0].calibration.parameters = test::parameters({"Tx", "CE"});
  bad[0].calibration.covariance = Eigen::Matrix2d::Identity();
  e = expect_error([&] { triangulate_point(bad); });
  EXPECT_NE(e.reason().find("mixes"), std::string::npos);

  bad = views;
  bad[1].pick_sigma_px = 0;
  e = expect_error([&] { triangulate_point(bad); });
  EXPECT_EQ(e.kind(), ErrorKind::input);
  EXPECT_EQ(e.field(), "pick_sigma_px");
}

}  // namespace
}  // namespace rangecal
