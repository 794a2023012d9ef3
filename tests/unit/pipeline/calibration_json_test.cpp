// calibration.json (docs/outputs.md): exact write → read round trip, deterministic bytes, the documented
// keys, σ from the covariance, centre covariance propagation, and bad files naming file and key.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "config/error.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "support/paths.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

CalibrationResult sample_result() {
  CalibrationResult r;
  r.camera_id = "cam1";
  r.method = "bundle";
  r.camera.id = "cam1";
  // Values with no short decimal form, to exercise exact round trips.
  r.camera.intr = {
      1280, 800, 0.02, 0.02, 135.0 + 1.0 / 3.0, 1.0 + 1e-4 / 7.0, 640.0 + 1.0 / 7.0, 400.0 - 2.0 / 9.0, {}};
  r.camera.intr.dist.k1 = -3.443e-4 / 3.0;
  r.camera.intr.dist.k2 = 1e-7 / 7.0;
  r.camera.intr.dist.p1 = -2e-6 / 3.0;
  r.camera.pose.R = Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  r.camera.pose.T = Eigen::Vector3d(1.0 / 3.0, -20.0 / 7.0, 64.0 + 1.0 / 11.0);
  r.parameters = test::parameters({"f", "k1", "wx", "wy", "wz", "Tx", "Ty", "Tz"});
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0, 1);
  Eigen::MatrixXd A(8, 8);
  for (int i = 0; i < 64; ++i) A(i) = n(rng) * 1e-3;
  r.covariance = A * A.transpose();
  Eigen::Matrix<double, 6, 6> cov_pose = r.covariance.bottomRightCorner(6, 6);
  r.center_covariance_m2 = center_covariance_from_pose(r.camera.pose.R, r.camera.pose.T, cov_pose);
  r.reprojection = {0.43 / 3.0, 0.35 / 7.0, 1.2 / 9.0, 1234, 5};
  r.rejected = {3, 17, 200, 1001, 1233};
  r.warnings = {"f and Tz correlated (0.995)"};
  r.details = {{"start", "tsai"}, {"iterations", 12}, {"cost", 1.0 / 3.0}};
  return r;
}

TEST(CalibrationIo, RoundTripIsExact) {
  CalibrationResult r = sample_result();
  r.clock_offset_s = 0.0021;
  const std::string text = calibration_to_json_text(r);
  const CalibrationResult b = calibration_from_json_text(text, "cal.json");
  EXPECT_EQ(b.camera_id, r.camera_id);
  EXPECT_EQ(b.method, r.method);
  EXPECT_EQ(b.camera.id, "cam1");
  const auto &x = r.camera.intr, &y = b.camera.intr;
  EXPECT_EQ(y.width_px, x.width_px);
  EXPECT_EQ(y.height_px, x.height_px);
  EXPECT_EQ(y.dx_mm, x.dx_mm);
  EXPECT_EQ(y.dy_mm, x.dy_mm);
  EXPECT_EQ(y.f_mm, x.f_mm);
  EXPECT_EQ(y.sx, x.sx);
  EXPECT_EQ(y.u0_px, x.u0_px);
  EXPECT_EQ(y.v0_px, x.v0_px);
  EXPECT_EQ(y.dist.as_array(), x.dist.as_array());
  EXPECT_TRUE(b.camera.pose.R == r.camera.pose.R);
  EXPECT_TRUE(b.camera.pose.T == r.camera.pose.T);
  EXPECT_EQ(b.parameters, r.parameters);
  EXPECT_TRUE(b.covariance == r.covariance);
  EXPECT_TRUE(b.center_covariance_m2 == r.center_covariance_m2);
  EXPECT_EQ(b.reprojection.rms_px, r.reprojection.rms_px);
  EXPECT_EQ(b.reprojection.mean_px, r.reprojection.mean_px);
  EXPECT_EQ(b.reprojection.max_px, r.reprojection.max_px);
  EXPECT_EQ(b.reprojection.n_used, 1234);
  EXPECT_EQ(b.reprojection.n_rejected, 5);
  EXPECT_EQ(b.rejected, r.rejected);
  EXPECT_EQ(b.warnings, r.warnings);
  EXPECT_EQ(b.details, r.details);
  EXPECT_EQ(b.clock_offset_s, 0.0021);
  // Byte-identical on a second write (deterministic, and the read lost nothing).
  EXPECT_EQ(calibration_to_json_text(b), text);
}

TEST(CalibrationIo, FileRoundTripAndSpecKeys) {
  const auto dir = test::scratch_dir("calibration_io_file");
  const std::string path = (dir / "cam1/calibration.json").string();
  const CalibrationResult r = sample_result();
  write_calibration_json(path, r);
  const std::string text = test::read_text(path);
  EXPECT_EQ(text, calibration_to_json_text(r));
  const auto j = nlohmann::json::parse(text);
  for (const char* k :
       {"camera", "method", "image_size_px", "pixel_size_um", "focal_mm", "sx", "principal_point_px",
        "distortion", "rotation_world_to_camera", "translation_m", "center_enu_m", "sigma", "reprojection"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_EQ(j["distortion"]["model"], "seed000_eq7");
  EXPECT_EQ(j["distortion"]["k1_per_mm2"].get<double>(), r.camera.intr.dist.k1);
  EXPECT_EQ(j["image_size_px"], nlohmann::json({1280, 800}));
  EXPECT_NEAR(j["pixel_size_um"][0].get<double>(), 20.0, 1e-12);
  EXPECT_EQ(j["rotation_world_to_camera"][1][2].get<double>(), r.camera.pose.R(1, 2));
  const Eigen::Vector3d C = r.camera.pose.center();
  EXPECT_EQ(j["center_enu_m"][2].get<double>(), C.z());
  for (const char* k : {"rms_px", "mean_px", "max_px", "n_used", "n_rejected"})
    EXPECT_TRUE(j["reprojection"].contains(k));
  // σ come from the covariance diagonal; parameters not estimated are null.
  EXPECT_EQ(j["sigma"]["focal_mm"].get<double>(), std::sqrt(r.covariance(0, 0)));
  EXPECT_EQ(j["sigma"]["k1_per_mm2"].get<double>(), std::sqrt(r.covariance(1, 1)));
  EXPECT_TRUE(j["sigma"]["principal_point_px"][0].is_null());
  EXPECT_TRUE(j["sigma"]["sx"].is_null());
  EXPECT_EQ(j["sigma"]["center_enu_m"][1].get<double>(), std::sqrt(r.center_covariance_m2(1, 1)));
  const CalibrationResult b = read_calibration_json(path);
  EXPECT_TRUE(b.covariance == r.covariance);
}

TEST(CalibrationIo, SigmaAndCorrelationAccessors) {
  const CalibrationResult r = sample_result();
  EXPECT_DOUBLE_EQ(r.sigma(CameraParameter::Tz), std::sqrt(r.covariance(7, 7)));
  EXPECT_TRUE(std::isnan(r.sigma(CameraParameter::u0)));
  EXPECT_DOUBLE_EQ(r.correlation(CameraParameter::f, CameraParameter::k1),
                   r.covariance(0, 1) / std::sqrt(r.covariance(0, 0) * r.covariance(1, 1)));
  CalibrationResult empty;
  EXPECT_TRUE(std::isnan(empty.sigma(CameraParameter::f)));
  EXPECT_TRUE(std::isnan(empty.center_sigma_m().x()));
  // Without covariance, every σ is written as null and reads back as not computed.
  empty.camera = r.camera;
  empty.camera_id = "c";
  empty.method = "tsai";
  const std::string t = calibration_to_json_text(empty);
  const auto j = nlohmann::json::parse(t);
  EXPECT_TRUE(j["sigma"]["focal_mm"].is_null());
  EXPECT_TRUE(j["covariance"]["center_enu_m2"].is_null());
  const CalibrationResult b = calibration_from_json_text(t, "c.json");
  EXPECT_EQ(b.covariance.size(), 0);
  EXPECT_TRUE(std::isnan(b.reprojection.rms_px));
  EXPECT_EQ(calibration_to_json_text(b), t);
}

// The first-order centre propagation against a Monte Carlo of the same pose perturbation model.
TEST(CalibrationIo, CenterCovarianceMatchesMonteCarlo) {
  const CalibrationResult r = sample_result();
  const Eigen::Matrix3d R = r.camera.pose.R;
  const Eigen::Vector3d T = r.camera.pose.T;
  Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
  cov.diagonal() << 1e-8, 4e-8, 2e-8, 1e-4, 2e-4, 9e-4;
  cov(0, 5) = cov(5, 0) = 1e-6;
  const Eigen::Matrix3d P = center_covariance_from_pose(R, T, cov);
  const Eigen::Matrix<double, 6, 6> L = cov.llt().matrixL();
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0, 1);
  const int N = 200000;
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  for (int k = 0; k < N; ++k) {
    Eigen::Matrix<double, 6, 1> z;
    for (int i = 0; i < 6; ++i) z(i) = n(rng);
    const Eigen::Matrix<double, 6, 1> d = L * z;
    const Eigen::Vector3d w = d.head<3>();
    const Eigen::Matrix3d Rp = (w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix()
                                             : Eigen::Matrix3d::Identity()) *
                               R;
    const Eigen::Vector3d C = -Rp.transpose() * (T + d.tail<3>()) - (-R.transpose() * T);
    S += C * C.transpose();
  }
  S /= N;
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(std::sqrt(S(i, i)), std::sqrt(P(i, i)), 0.01 * std::sqrt(P(i, i))) << i;
}

void expect_bad(const std::string& name, nlohmann::json j, const std::string& key, const std::string& words) {
  const auto path = (test::scratch_dir("calibration_bad_" + name) / "calibration.json").string();
  test::write_text(path, j.dump(2));
  try {
    read_calibration_json(path);
    FAIL() << name;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.field().rfind(key, 0), 0u) << name << ": " << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << name << ": " << e.what();
  }
}

TEST(CalibrationIo, BadFilesNameFileAndKey) {
  const auto good = nlohmann::json::parse(calibration_to_json_text(sample_result()));
  auto j = good;
  j.erase("focal_mm");
  expect_bad("missing_focal", j, "focal_mm", "missing required key");
  j = good;
  j["focal_mm"] = -135;
  expect_bad("negative_focal", j, "focal_mm", "positive");
  j = good;
  j["focla_mm"] = 1;
  expect_bad("typo", j, "focla_mm", "did you mean 'focal_mm'?");
  j = good;
  j["rotation_world_to_camera"][0][0] = 2.0;
  expect_bad("not_rotation", j, "rotation_world_to_camera", "not a rotation");
  j = good;
  j["center_enu_m"][0] = j["center_enu_m"][0].get<double>() + 0.5;
  expect_bad("center", j, "center_enu_m", "inconsistent");
  j = good;
  j["distortion"]["model"] = "brown";
  expect_bad("model", j, "distortion.model", "unknown distortion model");
  j = good;
  j["image_size_px"] = {1280};
  expect_bad("size", j, "image_size_px", "array of 2 positive integers");
  // The image side limit is config/physical_ranges.hpp's, 32768 px: one more is refused.
  j = good;
  j["image_size_px"] = {1280, 40000};
  expect_bad("size_limit", j, "image_size_px", "each ≤ 32768");
  j["image_size_px"] = {32769, 800};
  expect_bad("size_limit_edge", j, "image_size_px", "got an array of 2 elements");
  j["image_size_px"] = {32768, 800};
  // The 1280-px camera's distortion, taken 25 times farther out, moves the far corner by more
  // than its own radius (refused: vision/camera/distortion_validity.hpp); the size alone is tested.
  for (auto& [key, value] : j["distortion"].items())
    if (value.is_number()) value = 0.0;
  {
    const auto path = (test::scratch_dir("calibration_size_limit_ok") / "calibration.json").string();
    test::write_text(path, j.dump(2));
    EXPECT_EQ(read_calibration_json(path).camera.intr.width_px, 32768);
  }
  j = good;
  j["covariance"]["matrix"].erase(0);
  expect_bad("cov_shape", j, "covariance.matrix", "symmetric 8x8");
  j = good;
  j["translation_m"][1] = "x";
  expect_bad("translation_type", j, "translation_m", "the string \"x\"");
  j = good;
  j["clock_offset_s"] = 18.0;
  expect_bad("clock_offset", j, "clock_offset_s", "|x| ≤ 10");
  j = good;
  j["covariance"]["parameters"][1] = "focal";
  expect_bad("unknown_parameter", j, "covariance.parameters[1]", "unknown parameter 'focal'");
  j = good;
  j["covariance"]["parameters"][1] = "f";
  expect_bad("repeated_parameter", j, "covariance.parameters[1]", "listed twice");
  j = good;
  j["covariance"]["parameters"][2] = "CE";
  expect_bad("mixed_pose", j, "covariance.parameters", "mixes translation");
  const auto path = (test::scratch_dir("calibration_bad_syntax") / "calibration.json").string();
  test::write_text(path, "{\n  \"camera\": \"c\",\n  oops\n}\n");
  try {
    read_calibration_json(path);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), 3);
  }
  try {
    read_calibration_json("/nonexistent/calibration.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "/nonexistent/calibration.json");
  }
}

// The world frame is self-describing: the site origin round-trips exactly, files without it (older
// ones) still read, and a malformed one is an input error naming the key.
TEST(CalibrationIo, WorldFrameRoundTripsAndIsOptional) {
  CalibrationResult r = sample_result();
  EXPECT_FALSE(nlohmann::json::parse(calibration_to_json_text(r)).contains("world_frame"));
  EXPECT_FALSE(calibration_from_json_text(calibration_to_json_text(r), "old.json").site_origin);
  try {
    require_site_origin(r, "old.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "old.json");
    EXPECT_EQ(e.field(), "world_frame");
    EXPECT_NE(std::string(e.what()).find("geodetic coordinates are unavailable"), std::string::npos);
  }
  r.site_origin = GeodeticOrigin{53.0 + 1.0 / 3.0, -9.0 - 1.0 / 7.0, 21.0 + 1.0 / 9.0};
  const std::string text = calibration_to_json_text(r);
  const auto j = nlohmann::json::parse(text);
  EXPECT_EQ(j["world_frame"]["kind"], "local_enu");
  EXPECT_EQ(j["world_frame"]["ellipsoid"], "WGS84");
  EXPECT_EQ(j["world_frame"]["origin_lat_deg"].get<double>(), r.site_origin->lat_deg);
  const CalibrationResult b = calibration_from_json_text(text, "cal.json");
  ASSERT_TRUE(b.site_origin);
  EXPECT_EQ(b.site_origin->lat_deg, r.site_origin->lat_deg);
  EXPECT_EQ(b.site_origin->lon_deg, r.site_origin->lon_deg);
  EXPECT_EQ(b.site_origin->h_m, r.site_origin->h_m);
  EXPECT_EQ(&require_site_origin(b, "cal.json"), &*b.site_origin);
  EXPECT_EQ(calibration_to_json_text(b), text);

  auto bad = j;
  bad["world_frame"]["origin_lat_deg"] = 95.0;
  expect_bad("frame_lat", bad, "world_frame.origin_lat_deg", "[-90, 90]");
  bad = j;
  bad["world_frame"]["ellipsoid"] = "GRS80";
  expect_bad("frame_ellipsoid", bad, "world_frame.ellipsoid", "WGS84");
  bad = j;
  bad["world_frame"].erase("origin_h_m");
  expect_bad("frame_h", bad, "world_frame.origin_h_m", "missing required key");
}

}  // namespace
}  // namespace rangecal
