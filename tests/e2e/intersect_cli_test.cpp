// The intersect stage (docs/intersection.md, docs/outputs.md intersection.csv, §6 `rangecal intersect`):
// triangulated poles against the truth of synthetic seed-002-like cameras (1280×800, 20 µm, 135 mm, ~64 m
// from the poles), Table 4's mean row against hand computation, the predicted sigma_m against Monte Carlo,
// warnings that do not stop the other poles, the CSV format, and both CLI forms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/intersection_csv.hpp"
#include "pipeline/stages/intersect_stage.hpp"
#include "pipeline/steps/intersection.hpp"
#include "support/paths.hpp"
#include "support/pole_field.hpp"
#include "support/synthetic_camera.hpp"
#include "vision/triangulation/calibration_covariance.hpp"

namespace rangecal {
namespace {

// ---------------------------------------------------------------------------------------------
// Files and the CLI.

std::string picks_csv(const IntersectCamera& c) {
  std::string s = "id,u,v\n";
  char buf[128];
  for (const auto& p : c.picks) {
    std::snprintf(buf, sizeof buf, "%s,%.6f,%.6f\n", p.id.c_str(), p.uv.x(), p.uv.y());
    s += buf;
  }
  return s;
}

CalibrationResult calibration_of(const Camera& c) {
  CalibrationResult r;
  r.camera_id = c.id;
  r.method = "bundle";
  r.camera = c;
  return r;
}

std::string q(const std::filesystem::path& p) {
  return "'" + p.string() + "'";
}

TEST(IntersectCommand, StandaloneFormPrintsTriangulatedPoints) {
  const auto dir = test::scratch_dir("intersect_standalone");
  const auto views = test::pole_field_views();
  std::string args = "intersect";
  for (int k = 0; k < 2; ++k) {
    write_calibration_json((dir / (views[k].id + ".json")).string(), calibration_of(views[k].camera));
    test::write_text(dir / (views[k].id + ".csv"), picks_csv(views[k]));
    args += " --calibration " + q(dir / (views[k].id + ".json")) + " --observations " +
            q(dir / (views[k].id + ".csv"));
  }
  const auto r = test::run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CsvTable t = parse_csv(r.out, "stdout");
  ASSERT_EQ(t.header, (std::vector<std::string>{"id", "E", "N", "U", "rms_px"}));
  const auto poles = test::pole_field_truth();
  ASSERT_EQ(t.records.size(), poles.size());
  for (std::size_t i = 0; i < poles.size(); ++i) {
    EXPECT_EQ(t.text(t.records[i], 0), poles[i].id);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(t.number(t.records[i], 1 + k), poles[i].enu[k], 6e-5);
    EXPECT_LT(t.number(t.records[i], 4), 1e-3);
  }

  // Mismatched pair counts: usage error.
  const auto bad = test::run_cli("intersect --calibration " + q(dir / "cam1.json") + " --calibration " +
                                 q(dir / "cam2.json") + " --observations " + q(dir / "cam1.csv"));
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_NE(bad.err.find("--observations"), std::string::npos) << bad.err;
  // One pair only: usage error.
  EXPECT_EQ(test::run_cli("intersect --calibration " + q(dir / "cam1.json") + " --observations " +
                          q(dir / "cam1.csv"))
                .exit_code,
            2);

  // A malformed observations line: input error naming file and line.
  test::write_text(dir / "bad.csv", "id,u,v\nA1,100.5,200.25\nA2,12x,300\n");
  const auto malformed = test::run_cli("intersect --calibration " + q(dir / "cam1.json") +
                                       " --observations " + q(dir / "cam1.csv") + " --calibration " +
                                       q(dir / "cam2.json") + " --observations " + q(dir / "bad.csv"));
  EXPECT_EQ(malformed.exit_code, 3) << malformed.err;
  EXPECT_NE(malformed.err.find((dir / "bad.csv").string() + ":3"), std::string::npos) << malformed.err;
  EXPECT_NE(malformed.err.find("'u'"), std::string::npos) << malformed.err;
}

/// A mission folder: empty GNSS and frame inputs (the stage does not read them), poles.csv (ENU),
/// picks for three cameras, calibration.json for cam1 and cam2 only (cam3 "failed" calibration).
std::filesystem::path build_mission(const std::string& name, bool with_poles) {
  const auto dir = test::scratch_dir(name);
  test::write_text(dir / "pos.pos", "");
  test::write_text(dir / "frames.csv", "frame,file,utc\n");
  std::string poles = "id,role,E,N,U\n";
  char buf[160];
  for (const auto& p : test::pole_field_truth()) {
    std::snprintf(buf, sizeof buf, "%s,%s,%.4f,%.4f,%.4f\n", p.id.c_str(), to_string(p.role), p.enu.x(),
                  p.enu.y(), p.enu.z());
    poles += buf;
  }
  test::write_text(dir / "survey/poles.csv", poles);
  std::string cams;
  const auto views = test::pole_field_views();
  for (const auto& v : views) {
    test::write_text(dir / v.id / "poles_px.csv", picks_csv(v));
    cams += std::string(cams.empty() ? "" : ",") + R"({"id": ")" + v.id +
            R"(", "frames": {"timestamps": "frames.csv"},
      "sensor": {"width_px": 1280, "height_px": 800, "pixel_size_um": [20, 20]},
      "lens": {"nominal_focal_mm": 135}, "pole_observations": ")" +
            v.id + R"(/poles_px.csv"})";
  }
  CalibrationResult c1 = calibration_of(views[0].camera);
  c1.parameters = test::parameters({"f", "CE", "CN", "CU"});
  c1.covariance = Eigen::Vector4d(0.05 * 0.05, 0.02 * 0.02, 0.02 * 0.02, 0.02 * 0.02).asDiagonal();
  write_calibration_json((dir / "out/cam1/calibration.json").string(), c1);
  write_calibration_json((dir / "out/cam2/calibration.json").string(), calibration_of(views[1].camera));
  test::write_text(dir / "mission.json", std::string(R"({
    "mission": "intersect test", "site": {"origin": {"lat": 45.6, "lon": 122.8, "h": 150}},
    "gnss": {"pos_files": ["pos.pos"]}, "lever_arm": {"vertical_m": 0.25},)") +
                                             (with_poles ? R"( "poles": "survey/poles.csv",)" : "") +
                                             R"( "cameras": [)" + cams + R"(],
    "intersect": {"pick_sigma_px": 0.3}, "output_dir": "out"})");
  return dir;
}

TEST(IntersectCommand, StageFormWritesIntersectionCsvAndRunLog) {
  const auto dir = build_mission("intersect_stage", true);
  const auto r = test::run_cli("intersect " + q(dir / "mission.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("cam3"), std::string::npos) << r.out;  // the skipped camera is reported
  const auto rows = read_intersection_csv((dir / "out/intersection.csv").string());
  ASSERT_EQ(rows.size(), 6u);
  const auto truth = test::pole_field_truth();
  // Expected sigma_m from the same cameras, covariance and pick σ, computed here directly.
  auto views = test::pole_field_views();
  views.pop_back();
  CalibrationResult c1;
  c1.parameters = test::parameters({"f", "CE", "CN", "CU"});
  c1.covariance = Eigen::Vector4d(0.05 * 0.05, 0.02 * 0.02, 0.02 * 0.02, 0.02 * 0.02).asDiagonal();
  views[0].calibration = camera_covariance(c1);
  const IntersectionResult direct = intersect_poles(views, truth, 0.3);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].id, truth[i].id);
    EXPECT_LT(rows[i].dR, 1e-4);  // picks printed to 1e-6 px, coordinates to 0.1 mm
    EXPECT_NEAR(rows[i].sigma_m, direct.poles[i].sigma_m, 5e-5);
    EXPECT_GT(rows[i].sigma_m, 0.01);  // 2 cm centre σ of cam1 dominates the 0.3 px picks
  }
  const auto run = nlohmann::json::parse(test::read_text(dir / "out/run.json"));
  const auto& counts = run["stages"]["intersect"]["counts"];
  EXPECT_EQ(counts["poles_triangulated"], 8);
  EXPECT_EQ(counts["check_poles"], 6);
  EXPECT_EQ(counts["control_poles"], 2);
  EXPECT_EQ(counts["cameras_used"], nlohmann::json::array({"cam1", "cam2"}));
  EXPECT_LT(counts["max_dR_m"].get<double>(), 1e-4);
  EXPECT_NEAR(counts["mean_sigma_m"].get<double>(), direct.check.mean_sigma_m, 1e-5);
  const std::string warnings = run["stages"]["intersect"]["warnings"].dump();
  EXPECT_NE(warnings.find("cam3"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("calibrate"), std::string::npos) << warnings;
  // Rerun: byte-identical CSV.
  const std::string csv1 = test::read_text(dir / "out/intersection.csv");
  ASSERT_EQ(test::run_cli("--quiet intersect " + q(dir / "mission.json")).exit_code, 0);
  EXPECT_EQ(test::read_text(dir / "out/intersection.csv"), csv1);
  // Both forms at once: usage error.
  EXPECT_EQ(test::run_cli("intersect " + q(dir / "mission.json") + " --calibration " +
                          q(dir / "out/cam1/calibration.json"))
                .exit_code,
            2);
}

TEST(IntersectCommand, NoPolesSkipsInTheRunButFailsTheStageCommand) {
  const auto dir = build_mission("intersect_nopoles", false);
  const MissionConfig cfg = load_mission_config((dir / "mission.json").string());
  const StageLog log = run_intersect_stage(cfg);  // as `rangecal run` calls it
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_EQ(log.warnings[0], "no poles: intersection skipped");
  EXPECT_FALSE(std::filesystem::exists(dir / "out/intersection.csv"));
  const auto r = test::run_cli("intersect " + q(dir / "mission.json"));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("'poles'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("mission.json"), std::string::npos) << r.err;
}

TEST(IntersectCommand, NoCalibratedCameraWithPicksIsAnInputError) {
  const auto dir = build_mission("intersect_nocal", true);
  std::filesystem::remove_all(dir / "out");
  const auto r = test::run_cli("intersect " + q(dir / "mission.json"));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("calibration.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("rangecal calibrate"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace rangecal
