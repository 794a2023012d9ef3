// `rangecal project` (docs/cli.md): id,E,N,U in → id,u,v out, equal to the camera model's `project`;
// points behind the camera and malformed lines are errors naming file, line and field.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <sstream>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "support/paths.hpp"
#include "vision/camera/point_projection.hpp"

namespace rangecal {
namespace {

CalibrationResult test_calibration() {
  CalibrationResult r;
  r.camera_id = r.camera.id = "cam1";
  r.method = "tsai";
  r.camera.intr = {1280, 800, 0.02, 0.02, 135.2, 1.0003, 645.5, 396.25, {}};
  r.camera.intr.dist.k1 = -3.4e-4;
  // Camera at (64, 0, 1.5) looking west (−E) and level: x right = −N... built from axes directly.
  const Eigen::Vector3d C(64.0, 0.0, 1.5);
  Eigen::Matrix3d R;
  R.row(0) = Eigen::Vector3d(0, 1, 0).transpose();   // image right = north
  R.row(1) = Eigen::Vector3d(0, 0, -1).transpose();  // image down = −up
  R.row(2) = Eigen::Vector3d(-1, 0, 0).transpose();  // optical axis = west
  r.camera.pose.R = R;
  r.camera.pose.T = -R * C;
  return r;
}

const char* kPoints =
    "id,E,N,U\n"
    "lamp1,0,0,1.5\n"
    "lamp2,0.5,3.0,10.25\n"
    "P7,-2,-4.5,0.3\n";

TEST(ProjectPoints, MatchesCameraModel) {
  const CalibrationResult cal = test_calibration();
  const std::string out = project_points_csv(cal.camera, kPoints, "pts.csv");
  const CsvTable t = parse_csv(out, "out");
  ASSERT_EQ(t.header, (std::vector<std::string>{"id", "u", "v"}));
  ASSERT_EQ(t.records.size(), 3u);
  const CsvTable in = parse_csv(kPoints, "pts.csv");
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& r = in.records[i];
    Eigen::Vector2d uv;
    ASSERT_TRUE(project(cal.camera, {in.number(r, 1), in.number(r, 2), in.number(r, 3)}, &uv));
    EXPECT_EQ(t.text(t.records[i], 0), in.text(r, 0));
    EXPECT_NEAR(t.number(t.records[i], 1), uv.x(), 1e-6);
    EXPECT_NEAR(t.number(t.records[i], 2), uv.y(), 1e-6);
  }
  // The point on the optical axis lands on the principal point (independent of the model code).
  EXPECT_NEAR(t.number(t.records[0], 1), 645.5, 1e-6);
  EXPECT_NEAR(t.number(t.records[0], 2), 396.25, 1e-6);
}

TEST(ProjectPoints, PointBehindCameraNamesLine) {
  const CalibrationResult cal = test_calibration();
  try {
    project_points_csv(cal.camera, "id,E,N,U\na,0,0,0\nb,100,0,0\n", "pts.csv");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "pts.csv");
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("behind camera 'cam1'"), std::string::npos) << e.what();
  }
}

TEST(ProjectPoints, MissingColumnAndBadNumber) {
  const Camera cam = test_calibration().camera;
  try {
    project_points_csv(cam, "id,E,N\na,0,0\n", "pts.csv");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "pts.csv");
    EXPECT_NE(std::string(e.what()).find("U"), std::string::npos) << e.what();
  }
  try {
    project_points_csv(cam, "id,E,N,U\na,0,x,0\n", "pts.csv");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "N");
  }
}

// Through the CLI (pipeline/cli/project_command.cpp wired in cli.cpp).
TEST(ProjectCommand, CliWritesIdUvToStdout) {
  const auto dir = test::scratch_dir("project_command_cli");
  const CalibrationResult cal = test_calibration();
  write_calibration_json((dir / "calibration.json").string(), cal);
  test::write_text(dir / "pts.csv", kPoints);
  const auto res = test::run_cli("project --calibration " + (dir / "calibration.json").string() +
                                 " --points " + (dir / "pts.csv").string());
  ASSERT_EQ(res.exit_code, 0) << res.err;
  EXPECT_EQ(res.out, project_points_csv(cal.camera, kPoints, "pts.csv"));

  test::write_text(dir / "behind.csv", "id,E,N,U\nfar,200,0,1\n");
  const auto bad = test::run_cli("project --calibration " + (dir / "calibration.json").string() +
                                 " --points " + (dir / "behind.csv").string());
  EXPECT_EQ(bad.exit_code, 3);
  EXPECT_NE(bad.err.find("behind.csv:2"), std::string::npos) << bad.err;

  const auto missing = test::run_cli("project --calibration " + (dir / "nope.json").string() + " --points " +
                                     (dir / "pts.csv").string());
  EXPECT_EQ(missing.exit_code, 3);
  EXPECT_NE(missing.err.find("nope.json"), std::string::npos) << missing.err;

  const auto usage = test::run_cli("project --points " + (dir / "pts.csv").string());
  EXPECT_EQ(usage.exit_code, 2);
}

// A calibration whose distortion no lens can have (k1 = 1e6 mm⁻²: every point would land by the
// principal point) is refused when read, naming the file and the coefficient, by `project` and
// `intersect` alike; nothing is printed on stdout (vision/camera/distortion_validity.hpp).
TEST(ProjectCommand, ImpossibleDistortionIsRefusedNamingTheCalibrationFileAndField) {
  const auto dir = test::scratch_dir("project_command_bad_distortion");
  CalibrationResult cal = test_calibration();
  write_calibration_json((dir / "good.json").string(), cal);
  cal.camera.intr.dist.k1 = 1e6;
  write_calibration_json((dir / "bad.json").string(), cal);
  test::write_text(dir / "pts.csv", kPoints);
  test::write_text(dir / "picks.csv", "id,u,v\nP1,600,400\n");
  const std::string bad = (dir / "bad.json").string(), good = (dir / "good.json").string();
  const auto p = test::run_cli("project --calibration " + bad + " --points " + (dir / "pts.csv").string());
  EXPECT_EQ(p.exit_code, 3) << p.out;
  EXPECT_TRUE(p.out.empty()) << p.out;
  EXPECT_NE(p.err.find(bad + ": field 'distortion.k1_per_mm2'"), std::string::npos) << p.err;
  EXPECT_NE(p.err.find("invertible over its image"), std::string::npos) << p.err;
  const auto i =
      test::run_cli("intersect --calibration " + good + " --observations " + (dir / "picks.csv").string() +
                    " --calibration " + bad + " --observations " + (dir / "picks.csv").string());
  EXPECT_EQ(i.exit_code, 3) << i.out;
  EXPECT_TRUE(i.out.empty()) << i.out;
  EXPECT_NE(i.err.find(bad + ": field 'distortion.k1_per_mm2'"), std::string::npos) << i.err;
}

// A distortion that folds just beyond the image corner (r_f = 1/√(−3 k1) = 16 mm, the corner at
// 15.2 mm) is valid, but no distorted point reaches an undistorted radius above r_f·2/3 = 10.7 mm:
// a point imaged 21 mm off the axis cannot be projected, and the message names the points file,
// its line and the calibration file.
TEST(ProjectCommand, PointBeyondTheDistortionsFoldNamesBothFiles) {
  const auto dir = test::scratch_dir("project_command_fold");
  CalibrationResult cal = test_calibration();
  cal.camera.intr.dist.k1 = -1.0 / (3 * 16.0 * 16.0);
  write_calibration_json((dir / "cal.json").string(), cal);
  test::write_text(dir / "pts.csv", "id,E,N,U\nnear,0,0,1.5\nwide,0,10,1.5\n");
  const auto r = test::run_cli("project --calibration " + (dir / "cal.json").string() + " --points " +
                               (dir / "pts.csv").string());
  EXPECT_EQ(r.exit_code, 3) << r.out;
  EXPECT_NE(r.err.find((dir / "pts.csv").string() + ":3: field 'E,N,U'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(" + (dir / "cal.json").string() + ")"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace rangecal
