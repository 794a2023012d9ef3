// The calibrate stage end to end: methods on the same problem (noise-free recovery of the truth,
// where each method's model can), the files it writes, and its failures.
#include "pipeline/stages/calibrate_stage.hpp"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/persistence.hpp>

#include "config/error.hpp"
#include "support/paths.hpp"
#include "support/single_camera_mission.hpp"
#include "support/synthetic_camera.hpp"
#include "pipeline/io/calibration_json.hpp"

namespace rangecal {
namespace {

CalibrationProblem problem_for(const Camera& truth, const std::vector<PointCorrespondence>& pts,
                               std::vector<std::string> free) {
  CalibrationProblem p;
  p.camera_id = "cam1";
  p.sensor = {truth.intr.width_px, truth.intr.height_px, truth.intr.dx_mm, truth.intr.dy_mm};
  p.nominal_focal_mm = 135;
  p.priors.principal_point_px = Eigen::Vector2d(truth.intr.u0_px, truth.intr.v0_px);
  p.free = std::move(free);
  for (const auto& c : pts) {
    BundleObservation o;
    o.world = c.world;
    o.pixel = c.pixel;
    o.world_cov = Eigen::Matrix3d::Identity() * 1e-4;
    p.observations.push_back(o);
  }
  return p;
}

TEST(CalibrateStage, EveryMethodRecoversNoiseFreeTruth) {
  // Seed 002-like: narrow lens, k1, sx 1 — every method's model covers it.
  const Camera truth = test::range_camera(-3.4e-4, 1.0);
  const auto pts = test::observe(truth, test::range_world_points(truth));
  const auto p = problem_for(truth, pts, {"f", "k1", "pose"});
  for (const std::string m : {"tsai", "tsai_sassa", "dlt_lmqn", "bundle"}) {
    const CalibrationResult r = calibrate_camera(m, p);
    EXPECT_EQ(r.method, m);
    EXPECT_NEAR(r.camera.intr.f_mm / truth.intr.f_mm, 1.0, 1e-6) << m;
    EXPECT_NEAR(r.camera.intr.dist.k1, truth.intr.dist.k1, 1e-9) << m;
    EXPECT_LT((r.camera.pose.center() - truth.pose.center()).norm(), 1e-6) << m;
    EXPECT_LT(test::rotation_angle_between(r.camera.pose.R, truth.pose.R), 1e-8) << m;
    EXPECT_LT(r.reprojection.rms_px, 1e-6) << m;
    EXPECT_EQ(r.reprojection.n_used, static_cast<int>(pts.size())) << m;
  }
}

TEST(CalibrateStage, BundleAndDltLmqnReportSigmaForEveryFreeParameter) {
  const Camera truth = test::range_camera(-3.4e-4, 1.0);
  const auto pts = test::observe(truth, test::range_world_points(truth), 0.1, 0.01, 5);
  const auto p = problem_for(truth, pts, {"f", "k1", "pose"});
  for (const std::string m : {"dlt_lmqn", "bundle"}) {
    const CalibrationResult r = calibrate_camera(m, p);
    for (const char* n : {"f", "k1", "wx", "wy", "wz", "CE", "CN", "CU"}) {
      EXPECT_TRUE(std::isfinite(r.sigma(n)) && r.sigma(n) > 0) << m << " " << n;
    }
    EXPECT_TRUE(r.center_sigma_m().allFinite()) << m;
    // With 1 cm world noise at 64 m the estimate stays within 4σ of the truth.
    EXPECT_LT(std::abs(r.camera.intr.f_mm - truth.intr.f_mm), 4 * r.sigma("f")) << m;
  }
}

TEST(CalibrateStage, DegenerateGeometryIsACalibrationError) {
  const Camera truth = test::range_camera();
  std::vector<Eigen::Vector3d> line;
  const Eigen::Vector3d a = truth.pose.center() + truth.pose.R.transpose() * Eigen::Vector3d(0, 0, 64);
  for (int i = 0; i < 30; ++i) line.push_back(a + Eigen::Vector3d(0, 0, 0.3 * i));  // one vertical line
  const auto p = problem_for(truth, test::observe(truth, line), {"f", "k1", "pose"});
  for (const std::string m : {"tsai", "tsai_sassa", "dlt_lmqn", "bundle"}) {
    try {
      calibrate_camera(m, p);
      ADD_FAILURE() << m << " accepted points on one line";
    } catch (const Error& e) {
      EXPECT_EQ(e.exit_code(), 4) << m << ": " << e.what();
    }
  }
  EXPECT_THROW(calibrate_camera("planar", p), Error);
  EXPECT_THROW(calibrate_camera("nonsense", p), Error);
}

TEST(CalibrateStage, CliWritesCalibrationOpencvAndMethods) {
  const Camera truth = test::range_camera(-3.4e-4, 1.0);
  const auto pts = test::observe(truth, test::range_world_points(truth), 0.05, 0.005, 9);
  const auto dir = test::scratch_dir("calib_cli");
  test::write_single_camera_mission(
      dir, pts, 0.005, R"({"method": "bundle", "compare": ["tsai", "dlt_lmqn"]})", "calibrate test");
  const auto r = test::run_cli("calibrate '" + (dir / "mission.json").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const CalibrationResult cal = read_calibration_json((dir / "out/cam1/calibration.json").string());
  EXPECT_NEAR(cal.camera.intr.f_mm, truth.intr.f_mm, 4 * cal.sigma("f"));
  // camera_opencv.yml reproduces rangecal's projection with cv::projectPoints within 0.01 px.
  cv::FileStorage fs((dir / "out/cam1/camera_opencv.yml").string(), cv::FileStorage::READ);
  ASSERT_TRUE(fs.isOpened());
  cv::Mat K, D, rvec, tvec;
  fs["camera_matrix"] >> K;
  fs["distortion_coefficients"] >> D;
  fs["rvec"] >> rvec;
  fs["tvec"] >> tvec;
  std::vector<cv::Point3d> obj;
  for (const auto& c : pts) obj.emplace_back(c.world.x(), c.world.y(), c.world.z());
  std::vector<cv::Point2d> img;
  cv::projectPoints(obj, rvec, tvec, K, D, img);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    Eigen::Vector2d uv;
    ASSERT_TRUE(project(cal.camera, pts[i].world, &uv));
    EXPECT_LT(std::hypot(img[i].x - uv.x(), img[i].y - uv.y()), 0.01);
  }
  const std::string methods = test::read_text(dir / "out/cam1/methods.csv");
  EXPECT_NE(methods.find("\nbundle,"), std::string::npos);
  EXPECT_NE(methods.find("\ntsai,"), std::string::npos);
  EXPECT_NE(methods.find("\ndlt_lmqn,"), std::string::npos);
  // Residuals and use flags were written back.
  const auto back = read_correspondences_csv((dir / "out/cam1/correspondences.csv").string());
  ASSERT_EQ(back.size(), pts.size());
  EXPECT_TRUE(back[0].residual_px.has_value() && back[0].used.has_value());
  // Rerun → byte-identical calibration.json and methods.csv.
  const std::string cal1 = test::read_text(dir / "out/cam1/calibration.json");
  ASSERT_EQ(test::run_cli("--quiet calibrate '" + (dir / "mission.json").string() + "'").exit_code, 0);
  EXPECT_EQ(test::read_text(dir / "out/cam1/calibration.json"), cal1);
  EXPECT_EQ(test::read_text(dir / "out/cam1/methods.csv"), methods);
}

TEST(CalibrateStage, MissingCorrespondencesIsAnInputError) {
  const auto dir = test::scratch_dir("calib_missing");
  test::write_text(dir / "pos.pos", "");
  test::write_text(dir / "frames.csv", "frame,file,utc\n");
  test::write_text(dir / "mission.json", R"({
    "site": {"origin": {"lat": 45.6, "lon": 122.8, "h": 150}},
    "gnss": {"pos_files": ["pos.pos"]}, "lever_arm": {"vertical_m": 0.25},
    "cameras": [{"id": "cam1", "frames": {"timestamps": "frames.csv"},
                 "sensor": {"width_px": 1280, "height_px": 800, "pixel_size_um": [20, 20]},
                 "lens": {"nominal_focal_mm": 135}}]})");
  const auto r = test::run_cli("calibrate '" + (dir / "mission.json").string() + "'");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("correspondences.csv"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("detect"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace rangecal
