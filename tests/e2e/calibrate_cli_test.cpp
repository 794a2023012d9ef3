// The calibrate stage end to end: methods on the same problem (noise-free recovery of the truth,
// where each method's model can), the files it writes, and its failures.
#include "pipeline/stages/calibrate_stage.hpp"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/persistence.hpp>

#include "config/error.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/residuals_csv.hpp"
#include "pipeline/steps/calibration_methods.hpp"
#include "support/paths.hpp"
#include "support/single_camera_mission.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

TEST(CalibrateStage, CliWritesCalibrationOpencvAndMethods) {
  const Camera truth = test::range_camera(-3.4e-4, 1.0);
  const auto pts = test::observe(truth, test::range_world_points(truth), 0.05, 0.005, 9);
  const auto dir = test::scratch_dir("calib_cli");
  test::write_single_camera_mission(
      dir, pts, 0.005, R"({"method": "bundle", "compare": ["tsai", "dlt_lmqn"]})", "calibrate test");
  const auto r = test::run_cli("calibrate '" + (dir / "mission.json").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const CalibrationResult cal = read_calibration_json((dir / "out/cam1/calibration.json").string());
  EXPECT_NEAR(cal.camera.intr.f_mm, truth.intr.f_mm, 4 * cal.sigma(CameraParameter::f));
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
  // Residuals and use flags are in residuals.csv; correspondences.csv stays as written (one
  // writer per file).
  const auto residuals = read_residuals_csv((dir / "out/cam1/residuals.csv").string());
  ASSERT_EQ(residuals.size(), pts.size());
  EXPECT_TRUE(residuals[0].d_px.has_value());
  EXPECT_TRUE(residuals[0].used);
  const auto back = read_correspondences_csv((dir / "out/cam1/correspondences.csv").string());
  ASSERT_EQ(back.size(), pts.size());
  EXPECT_FALSE(back[0].residual_px.has_value() || back[0].used.has_value());
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
