// Cameras calibrated elsewhere (pipeline/io/imported_calibration.hpp; docs/trajectory.md "Imported
// calibrations"): their trajectory σ holds over many missions when the user states the calibration's
// σ, and under-covers without it.
//
// Each of 30 missions: a drone (8 m/s at 50–100 m) seen by three 25-mm cameras at 50, 60 and 120
// frames/s, not synchronised, time code to 1 ms, labels 0.5 px. Each camera was "calibrated
// elsewhere": its truth moved by a draw from the σ its user states (focal length, principal point,
// attitude, centre), then written by rangecal's exporters as a real file — two as OpenCV camera YAML
// (wide lenses with k1; the import fits rangecal's inverse distortion to OpenCV's), one as a DLT-11
// coefficient column (a pinhole) — and read back through the import the trajectory stage uses. The
// labels are the true cameras' projections of the simulated path. Asserted: error / predicted σ
// (z rms) within [0.8, 1.25], the 95 % ellipsoid covering 93–97 % of the instants, and under 85 %
// when the stated σ is ignored.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include "config/atomic_file.hpp"
#include "config/error.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/imported_calibration.hpp"
#include "support/expect_error.hpp"
#include "support/paths.hpp"
#include "support/synthetic_camera.hpp"
#include "vision/camera/dlt_export.hpp"
#include "vision/camera/opencv_camera_export.hpp"
#include "vision/triangulation/target_trajectory.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

constexpr std::int64_t kT0 = 1'800'000'000'000'000'000;
constexpr double kSeconds = 3.0, kLabelPx = 0.5, kTimingS = 1e-3, kRateHz = 25;
constexpr double kFps[3] = {50, 60, 120};
constexpr double kChi2_3_95 = 7.814727903251178;

// What each camera's user states (and what the truth is drawn from).
StatedCalibrationSigma stated() {
  StatedCalibrationSigma s;
  s.focal_px = 4;
  s.principal_point_px = 2;
  s.position_m = 0.02;
  s.rotation_mrad = 0.15;
  return s;
}

Eigen::Vector3d path(double t) {
  const double s = t - 0.5 * kSeconds;
  return {8 * s, 0.4 * s, 15 + 0.16 * s};
}

struct Mission {
  std::vector<TrajectoryCamera> cameras;
};

Mission simulate(const fs::path& dir, std::mt19937_64* rng) {
  std::normal_distribution<double> n01(0, 1);
  std::uniform_real_distribution<double> u01(0, 1);
  const StatedCalibrationSigma sg = stated();
  Mission m;
  const double bearings[3] = {-2.0, -1.1, -0.3};
  for (int k = 0; k < 3; ++k) {
    const bool dlt = k == 1;
    const double range = 50 + 50 * (0.25 + 0.5 * u01(*rng));
    const Eigen::Vector3d centre(range * std::cos(bearings[k]), range * std::sin(bearings[k]), 2);
    const std::string id = "cam" + std::to_string(k);
    Camera truth = test::range_camera_at(id, centre, path(0.5 * kSeconds), dlt ? 0.0 : -1e-4,
                                         Eigen::Vector2d(652.0 - 9 * k, 391.0 + 6 * k));
    truth.intr.f_mm = 25;
    const double sd[9] = {sg.focal_px * truth.intr.dy_mm,
                          sg.principal_point_px,
                          sg.principal_point_px,
                          1e-3 * sg.rotation_mrad,
                          1e-3 * sg.rotation_mrad,
                          1e-3 * sg.rotation_mrad,
                          sg.position_m,
                          sg.position_m,
                          sg.position_m};
    // The calibration made elsewhere, drawn here without the library's parameter code: f and the
    // principal point moved, the attitude turned by a small rotation about the camera's axes
    // (R = exp([w]×)·R̂), the centre moved in site ENU.
    Camera elsewhere = truth;
    elsewhere.intr.f_mm += sd[0] * n01(*rng);
    elsewhere.intr.u0_px += sd[1] * n01(*rng);
    elsewhere.intr.v0_px += sd[2] * n01(*rng);
    const Eigen::Vector3d w(sd[3] * n01(*rng), sd[4] * n01(*rng), sd[5] * n01(*rng));
    const Eigen::Vector3d centre_elsewhere =
        truth.pose.center() + Eigen::Vector3d(sd[6] * n01(*rng), sd[7] * n01(*rng), sd[8] * n01(*rng));
    elsewhere.pose.R = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() * truth.pose.R;
    elsewhere.pose.T = -elsewhere.pose.R * centre_elsewhere;

    ImportedCameraConfig cfg;
    cfg.id = id;
    cfg.sensor.width_px = truth.intr.width_px;
    cfg.sensor.height_px = truth.intr.height_px;
    cfg.sensor.pixel_size_um[0] = 1e3 * truth.intr.dx_mm;
    cfg.sensor.pixel_size_um[1] = 1e3 * truth.intr.dy_mm;
    cfg.sigma = sg;
    if (dlt) {
      cfg.dlt = (dir / (id + "_dlt.csv")).string();
      write_file_atomic(cfg.dlt, dlt_coefficients_csv({dlt_camera(elsewhere)}));
    } else {
      cfg.opencv_yml = (dir / (id + ".yml")).string();
      write_opencv_camera_yml(cfg.opencv_yml, fit_opencv_camera(elsewhere));
    }
    const ImportedCalibration imported = read_imported_calibration(cfg, GeodeticOrigin{});
    EXPECT_LT(imported.fit_max_px, 0.05) << id;

    TrajectoryCamera tc;
    tc.id = id;
    tc.camera = imported.camera;
    tc.calibration = imported.covariance;
    tc.model_sigma_px = imported.model_sigma_px;
    tc.label_sigma_px = kLabelPx;
    const double start = u01(*rng) / kFps[k];
    for (int j = 0; start + j / kFps[k] < kSeconds; ++j) {
      const double stamp = start + j / kFps[k];
      TimedLabel l;
      l.t = UtcTime{kT0 + std::llround(stamp * 1e9)};
      if (!project(truth, path(stamp + kTimingS * n01(*rng)), &l.uv_px)) continue;
      l.uv_px += kLabelPx * Eigen::Vector2d(n01(*rng), n01(*rng));
      l.timing_sigma_s = kTimingS;
      tc.labels.push_back(l);
    }
    m.cameras.push_back(std::move(tc));
  }
  return m;
}

TEST(ImportedCalibration, TheStatedSigmaCarriesTheTrajectory) {
  const fs::path dir = test::scratch_dir("imported_calibration_sigma");
  std::mt19937_64 rng(41);
  double z2 = 0, e2 = 0;
  std::size_t n = 0, inside = 0, inside_without = 0;
  for (int mission = 0; mission < 30; ++mission) {
    const Mission m = simulate(dir, &rng);
    const Trajectory tr = estimate_trajectory(m.cameras, trajectory_instants(m.cameras, kRateHz), nullptr);
    for (const TrajectoryPoint& p : tr.points) {
      if (p.cameras.size() < 3) continue;
      const Eigen::Vector3d e = p.fix.point - path(1e-9 * static_cast<double>(p.t.ns - kT0));
      const Eigen::Matrix3d without = p.fix.cov_pick_m2 + p.fix.cov_timing_m2;
      z2 += e.squaredNorm() / (p.fix.sigma_m * p.fix.sigma_m);
      e2 += e.squaredNorm();
      inside += e.dot(p.fix.cov_m2.ldlt().solve(e)) <= kChi2_3_95 ? 1 : 0;
      inside_without += e.dot(without.ldlt().solve(e)) <= kChi2_3_95 ? 1 : 0;
      ++n;
    }
  }
  ASSERT_GT(n, 1000u);
  const double z = std::sqrt(z2 / n), cover = static_cast<double>(inside) / n,
               cover_without = static_cast<double>(inside_without) / n;
  std::printf(
      "imported (2 OpenCV YAML, 1 DLT-11): %zu instants over 30 missions: rms %.2f cm, z rms %.3f, 95%% "
      "ellipsoid covers %.1f%% (%.1f%% without the stated σ)\n",
      n, 100 * std::sqrt(e2 / n), z, 100 * cover, 100 * cover_without);
  EXPECT_GT(z, 0.8);
  EXPECT_LT(z, 1.25);
  EXPECT_GT(cover, 0.93);
  EXPECT_LT(cover, 0.97);
  EXPECT_LT(cover_without, 0.85);
}

TEST(ImportedCalibration, TheStatedSigmaIsTheCovarianceOfTheParameters) {
  Camera cam;
  cam.id = "c";
  cam.intr.dy_mm = 0.0055;
  StatedCalibrationSigma s = stated();
  const CameraCovariance c = stated_camera_covariance(cam, s);
  ASSERT_EQ(c.parameters.size(), 9u);
  EXPECT_EQ(c.parameters[0], CameraParameter::f);
  EXPECT_DOUBLE_EQ(c.covariance(0, 0), std::pow(4 * 0.0055, 2));  // 4 px of focal length in mm
  EXPECT_DOUBLE_EQ(c.covariance(1, 1), 4.0);
  EXPECT_DOUBLE_EQ(c.covariance(3, 3), std::pow(0.15e-3, 2));
  EXPECT_DOUBLE_EQ(c.covariance(8, 8), std::pow(0.02, 2));
  EXPECT_DOUBLE_EQ(c.covariance.sum(), c.covariance.diagonal().sum());
  s.principal_point_px = 0;  // a principal point stated exact is left out
  EXPECT_EQ(stated_camera_covariance(cam, s).parameters.size(), 7u);
  EXPECT_TRUE(stated_camera_covariance(cam, StatedCalibrationSigma{}).parameters.empty());
  s.position_m = -1;
  EXPECT_THROW(stated_camera_covariance(cam, s), Error);
}

// The model's σ adds to every view's label σ in quadrature: labels of 3 px with a model σ of 4 px
// weigh as labels of 5 px.
TEST(ImportedCalibration, TheModelSigmaAddsInQuadrature) {
  std::mt19937_64 rng(5);
  const fs::path dir = test::scratch_dir("imported_calibration_quadrature");
  Mission m = simulate(dir, &rng);
  std::vector<TrajectoryCamera> stated = m.cameras, plain = m.cameras;
  for (std::size_t k = 0; k < stated.size(); ++k) {
    stated[k].calibration = plain[k].calibration = {};
    stated[k].label_sigma_px = 3;
    stated[k].model_sigma_px = 4;
    plain[k].label_sigma_px = 5;
    plain[k].model_sigma_px = 0;
  }
  const std::vector<UtcTime> instants = trajectory_instants(plain, kRateHz);
  const Trajectory a = estimate_trajectory(stated, instants, nullptr),
                   b = estimate_trajectory(plain, instants, nullptr);
  ASSERT_EQ(a.points.size(), b.points.size());
  ASSERT_GT(a.points.size(), 50u);
  for (std::size_t i = 0; i < a.points.size(); ++i)
    EXPECT_LT((a.points[i].fix.cov_pick_m2 - b.points[i].fix.cov_pick_m2).norm(),
              1e-9 * b.points[i].fix.cov_pick_m2.norm());
  stated[0].model_sigma_px = -1;
  EXPECT_THROW(estimate_trajectory(stated, instants, nullptr), Error);
}

// Another mission's calibration.json: the camera and its covariance as written; refused when a
// parameter the σ needs is left out (it would be exact), the matrix states no uncertainty, the
// image is another, or the pose is in another site's frame (or in none).
TEST(ImportedCalibration, ACalibrationJsonComesWithItsWholeCovariance) {
  const fs::path dir = test::scratch_dir("imported_calibration_json");
  const GeodeticOrigin site{45.6, 122.8, 150.0};
  Camera cam = test::range_camera_at("lab", {-30, -55, 2}, path(1.5));
  CalibrationResult r;
  r.camera_id = "lab";
  r.method = "bundle";
  r.camera = cam;
  r.site_origin = site;
  r.parameters = {CameraParameter::f,  CameraParameter::k1, CameraParameter::u0, CameraParameter::v0,
                  CameraParameter::wx, CameraParameter::wy, CameraParameter::wz, CameraParameter::CE,
                  CameraParameter::CN, CameraParameter::CU};
  Eigen::MatrixXd a = Eigen::MatrixXd::Random(10, 10);
  const Eigen::MatrixXd spd = 1e-6 * (a * a.transpose() + Eigen::MatrixXd::Identity(10, 10));
  r.covariance = 0.5 * (spd + spd.transpose());  // symmetric to the bit, as calibration.json requires
  const auto imported = [&](const CalibrationResult& res) {
    write_calibration_json((dir / "calibration.json").string(), res);
    ImportedCameraConfig cfg;
    cfg.id = "lab1";
    cfg.rangecal_json = (dir / "calibration.json").string();
    cfg.sensor.width_px = 1280;
    cfg.sensor.height_px = 800;
    return read_imported_calibration(cfg, site);
  };
  const ImportedCalibration ok = imported(r);
  EXPECT_EQ(ok.format, "rangecal_json");
  EXPECT_EQ(ok.camera.id, "lab1");
  EXPECT_NEAR(ok.camera.intr.f_mm, cam.intr.f_mm, 1e-9);
  EXPECT_NEAR((ok.camera.pose.center() - cam.pose.center()).norm(), 0, 1e-9);
  ASSERT_EQ(ok.covariance.parameters, r.parameters);
  EXPECT_LT((ok.covariance.covariance - r.covariance).norm(), 1e-12 * r.covariance.norm() + 1e-18);

  CalibrationResult no_pp = r;
  no_pp.parameters = {CameraParameter::f,  CameraParameter::wx, CameraParameter::wy, CameraParameter::wz,
                      CameraParameter::CE, CameraParameter::CN, CameraParameter::CU};
  no_pp.covariance = r.covariance.topLeftCorner(7, 7);
  Error e = test::expect_error([&] { imported(no_pp); });
  EXPECT_EQ(e.exit_code(), 3);
  EXPECT_EQ(e.field(), "covariance");
  EXPECT_NE(e.reason().find("leaves out u0, v0"), std::string::npos) << e.reason();

  // Every variance positive and every correlation within ±0.9, yet no covariance: f, u0 and v0
  // correlated +0.9, +0.9 and −0.9 have a negative eigenvalue.
  CalibrationResult negative = r;
  Eigen::MatrixXd corr = Eigen::MatrixXd::Identity(10, 10);
  corr(0, 2) = corr(2, 0) = corr(0, 3) = corr(3, 0) = 0.9;
  corr(2, 3) = corr(3, 2) = -0.9;
  const Eigen::VectorXd sd = r.covariance.diagonal().cwiseSqrt();
  const Eigen::MatrixXd indefinite = sd.asDiagonal() * corr * sd.asDiagonal();
  negative.covariance = 0.5 * (indefinite + indefinite.transpose());
  e = test::expect_error([&] { imported(negative); });
  EXPECT_NE(e.reason().find("positive semi-definite"), std::string::npos) << e.reason();

  CalibrationResult other_site = r;
  other_site.site_origin = GeodeticOrigin{45.6, 122.8, 151.0};
  e = test::expect_error([&] { imported(other_site); });
  EXPECT_EQ(e.field(), "world_frame");

  CalibrationResult no_site = r;
  no_site.site_origin.reset();
  e = test::expect_error([&] { imported(no_site); });
  EXPECT_EQ(e.field(), "world_frame");

  CalibrationResult wide = r;
  wide.camera.intr.width_px = 1920;
  e = test::expect_error([&] { imported(wide); });
  EXPECT_EQ(e.field(), "image_size_px");
}

}  // namespace
}  // namespace rangecal
