// `rangecal trajectory CONFIG` (alias `track`) on missions that give it nothing to do or lack what it
// reads: a clear error or a partial outcome naming the cause, never exit 0 with an empty answer.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <tuple>
#include <vector>

#include "config/csv_table.hpp"
#include "config/deterministic_random.hpp"
#include "gnss/time/utc_time.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "support/paths.hpp"
#include "support/synthetic_camera.hpp"
#include "vision/camera/dlt_export.hpp"
#include "vision/camera/opencv_camera_export.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

nlohmann::json mission(const fs::path& dir) {
  test::write_text(dir / "rover.pos", "% empty\n");
  test::write_text(dir / "target.csv", "frame,u,v\n1,100,100\n2,101,101\n");
  test::write_text(dir / "times.csv", "frame,utc\n1,2026-05-04T10:00:00Z\n2,2026-05-04T10:00:00.02Z\n");
  nlohmann::json j = {{"site", {{"origin", {{"lat", 45.6}, {"lon", 122.8}, {"h", 150.0}}}}},
                      {"gnss", {{"pos_files", {(dir / "rover.pos").string()}}}},
                      {"lever_arm", {{"vertical_m", 0.25}}},
                      {"output_dir", (dir / "out").string()}};
  for (const char* id : {"cam1", "cam2"})
    j["cameras"].push_back(
        {{"id", id},
         {"sensor", {{"width_px", 1280}, {"height_px", 800}, {"pixel_size_um", {20, 20}}}},
         {"lens", {{"nominal_focal_mm", 135}}},
         {"target_track",
          {{"file", (dir / "target.csv").string()}, {"timestamps", (dir / "times.csv").string()}}}});
  return j;
}

TEST(TrajectoryCli, NoTargetTrackIsAnInputError) {
  const fs::path dir = test::scratch_dir("trajectory_cli_none");
  nlohmann::json j = mission(dir);
  for (auto& cam : j["cameras"]) cam.erase("target_track");
  test::write_text(dir / "m.json", j.dump());
  const auto r = test::run_cli("trajectory '" + (dir / "m.json").string() + "'");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("cameras[].target_track"), std::string::npos) << r.err;
}

TEST(TrajectoryCli, UncalibratedCamerasMakeThePartialOutcomeNamingTheirFiles) {
  const fs::path dir = test::scratch_dir("trajectory_cli_uncalibrated");
  test::write_text(dir / "m.json", mission(dir).dump());
  const auto r = test::run_cli("track '" + (dir / "m.json").string() + "'");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.out.find("cam1/calibration.json"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("two calibrated cameras"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "trajectory.csv"));
}

// Two cameras calibrated elsewhere and nothing calibrated by the mission (docs/trajectory.md "Imported
// calibrations"): one as an OpenCV camera YAML (a lens with k1), one as the second column of a DLT-11
// coefficient file; a drone flying a straight line at 6 m/s, 60 m out, each camera's labels the true
// projection with 0.2 px of noise at 30 and 25 frames/s. The files hold the true cameras, so the
// trajectory's error is the labels' alone: within 4σ of the simulated path at every instant.
constexpr std::int64_t kT0 = 1'780'000'000'000'000'000;

Eigen::Vector3d drone(double t) {
  return {-9 + 6 * t, 0.5 * t, 12 + 0.3 * t};
}

void write_labels(const Camera& cam, double fps, const fs::path& dir, DeterministicRandom* rng) {
  std::string labels = "frame,u,v\n", times = "frame,utc\n";
  for (int k = 0; k / fps < 3.0; ++k) {
    Eigen::Vector2d uv;
    if (!project(cam, drone(k / fps), &uv)) continue;
    char line[96];
    std::snprintf(line, sizeof line, "%d,%.4f,%.4f\n", k, uv.x() + 0.2 * rng->normal(),
                  uv.y() + 0.2 * rng->normal());
    labels += line;
    times += std::to_string(k) + "," + format_iso8601_utc(UtcTime{kT0 + std::llround(k / fps * 1e9)}) + "\n";
  }
  test::write_text(dir / (cam.id + "_labels.csv"), labels);
  test::write_text(dir / (cam.id + "_times.csv"), times);
}

// A calibration.json of `cam` as another mission on the site `origin` would have written it, with a
// covariance over f, u0, v0 and the pose whose centre and focal length are correlated.
void write_rangecal_json(const Camera& cam, const GeodeticOrigin& origin, const fs::path& path) {
  CalibrationResult r;
  r.camera_id = cam.id;
  r.method = "network";
  r.camera = cam;
  r.site_origin = origin;
  r.parameters = {CameraParameter::f,  CameraParameter::u0, CameraParameter::v0,
                  CameraParameter::wx, CameraParameter::wy, CameraParameter::wz,
                  CameraParameter::CE, CameraParameter::CN, CameraParameter::CU};
  Eigen::VectorXd sd(9);
  sd << 0.02, 1.0, 1.0, 5e-5, 5e-5, 5e-5, 0.01, 0.01, 0.01;
  r.covariance = sd.cwiseAbs2().asDiagonal();
  r.covariance(0, 8) = r.covariance(8, 0) = 0.8 * sd[0] * sd[8];
  write_calibration_json(path.string(), r);
}

nlohmann::json imported_mission(const fs::path& dir) {
  Camera a = test::range_camera_at("lab_a", {-30, -55, 2}, drone(1.5), -1.5e-4, {655.0, 388.0});
  Camera b = test::range_camera_at("lab_b", {35, -50, 3}, drone(1.5), 0.0, {630.0, 410.0});
  a.intr.f_mm = b.intr.f_mm = 35;
  write_opencv_camera_yml((dir / "lab_a.yml").string(), fit_opencv_camera(a));
  Camera other = b;  // the file's first column: another camera of the same survey
  other.id = "lab_c";
  other.pose.T += Eigen::Vector3d(1, 0, 0);
  test::write_text(dir / "dlt.csv", dlt_coefficients_csv({dlt_camera(other), dlt_camera(b)}));
  DeterministicRandom rng(37);
  Camera c = test::range_camera_at("lab_c", {5, -70, 2}, drone(1.5), -1e-4, {640.0, 402.0});
  c.intr.f_mm = 35;
  write_rangecal_json(c, {45.6, 122.8, 150.0}, dir / "lab_c.json");
  write_labels(a, 30, dir, &rng);
  write_labels(b, 25, dir, &rng);
  write_labels(c, 20, dir, &rng);
  nlohmann::json j = mission(dir);
  j["cameras"] = nlohmann::json::array();
  const nlohmann::json sensor = {{"width_px", 1280}, {"height_px", 800}, {"pixel_size_um", {20, 20}}};
  const nlohmann::json sigma = {
      {"focal_px", 1.0}, {"principal_point_px", 1.0}, {"position_m", 0.01}, {"rotation_mrad", 0.05}};
  for (const auto& [id, calibration] :
       {std::pair<std::string, nlohmann::json>{"lab_a", {{"opencv_yml", (dir / "lab_a.yml").string()}}},
        {"lab_b", {{"dlt", (dir / "dlt.csv").string()}, {"column", 2}}},
        {"lab_c", {{"rangecal_json", (dir / "lab_c.json").string()}}}})
    j["trajectory"]["imported_cameras"].push_back({{"id", id},
                                                   {"calibration", calibration},
                                                   {"sensor", sensor},
                                                   {"sigma", sigma},
                                                   {"label_sigma_px", 0.2},
                                                   {"target_track",
                                                    {{"file", (dir / (id + "_labels.csv")).string()},
                                                     {"timestamps", (dir / (id + "_times.csv")).string()}}}});
  j["trajectory"]["imported_cameras"][2].erase("sigma");  // calibration.json states its own
  return j;
}

TEST(TrajectoryCli, ImportedCalibrationsAloneGiveATrajectory) {
  const fs::path dir = test::scratch_dir("trajectory_cli_imported");
  test::write_text(dir / "m.json", imported_mission(dir).dump(2));
  const auto r = test::run_cli("track '" + (dir / "m.json").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const CsvTable rows = parse_csv(test::read_text(dir / "out" / "trajectory.csv"), "trajectory.csv");
  ASSERT_GT(rows.records.size(), 60u);
  double worst_z = 0;
  for (const CsvRecord& row : rows.records) {
    const double t =
        1e-9 * static_cast<double>(parse_iso8601_utc(rows.text(row, rows.column("utc")))->ns - kT0);
    const Eigen::Vector3d enu(rows.number(row, rows.column("E")), rows.number(row, rows.column("N")),
                              rows.number(row, rows.column("U")));
    worst_z = std::max(worst_z, (enu - drone(t)).norm() / rows.number(row, rows.column("sigma_labels_m")));
  }
  std::printf("imported cameras alone: %zu instants, worst |error| / σ of the labels %.2f\n",
              rows.records.size(), worst_z);
  EXPECT_LT(worst_z, 4.0);
  const auto run = nlohmann::json::parse(test::read_text(dir / "out" / "run.json"));
  const auto& cams = run["stages"]["trajectory"]["counts"]["cameras"];
  EXPECT_EQ(cams["lab_a"]["imported_calibration"]["format"], "opencv_yml");
  EXPECT_EQ(cams["lab_b"]["imported_calibration"]["format"], "dlt");
  EXPECT_EQ(cams["lab_c"]["imported_calibration"]["format"], "rangecal_json");
  EXPECT_LT(cams["lab_b"]["imported_calibration"]["conversion_max_px"].get<double>(), 1e-3);
  EXPECT_LT(cams["lab_a"]["imported_calibration"]["conversion_max_px"].get<double>(), 0.05);
  // run.json and trajectory.json state one median: the ⌈n/2⌉-th smallest of trajectory.csv's values
  // as written, computed here.
  const auto summary = nlohmann::json::parse(test::read_text(dir / "out" / "trajectory.json"));
  const auto& counts = run["stages"]["trajectory"]["counts"];
  for (const auto& [key, column, part] :
       {std::tuple<const char*, const char*, const char*>{"median_sigma_m", "sigma_m", "median"},
        {"median_sigma_labels_m", "sigma_labels_m", "labels_median"},
        {"median_sigma_calibration_m", "sigma_calibration_m", "calibration_median"}}) {
    std::vector<double> v;
    for (const CsvRecord& row : rows.records) v.push_back(rows.number(row, rows.column(column)));
    std::sort(v.begin(), v.end());
    const double median = v[(v.size() + 1) / 2 - 1];
    EXPECT_DOUBLE_EQ(counts[key].get<double>(), median) << key;
    EXPECT_DOUBLE_EQ(summary["sigma_m"][part].get<double>(), median) << part;
  }
  EXPECT_GT(counts["median_sigma_calibration_m"].get<double>(), 0);
}

// The same cameras with the labels' σ a guess five times too large (1 px; 0.2 px true), estimated
// from the views (`trajectory.label_sigma: "estimate"`, docs/trajectory.md "Label σ"): every camera's
// σ comes back near 0.2 px — a little below: the files hold the true cameras, while the σ they state
// allows a pixel of principal point, whose share of the residuals is then missing — and run.json and
// trajectory.json say how it was set.
TEST(TrajectoryCli, ALabelSigmaGuessedIsEstimatedFromTheViews) {
  const fs::path dir = test::scratch_dir("trajectory_cli_label_sigma");
  nlohmann::json j = imported_mission(dir);
  for (auto& cam : j["trajectory"]["imported_cameras"]) cam["label_sigma_px"] = 1.0;
  j["trajectory"]["label_sigma"] = "estimate";
  test::write_text(dir / "m.json", j.dump(2));
  const auto r = test::run_cli("track '" + (dir / "m.json").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto run = nlohmann::json::parse(test::read_text(dir / "out" / "run.json"));
  const auto& counts = run["stages"]["trajectory"]["counts"];
  EXPECT_EQ(counts["label_sigma"]["mode"], "estimate");
  EXPECT_TRUE(counts["label_sigma"]["converged"].get<bool>());
  for (const char* id : {"lab_a", "lab_b", "lab_c"}) {
    const auto& cam = counts["cameras"][id];
    std::printf("%s: label σ %.3f ± %.3f px (given %.1f), %s\n", id, cam["label_sigma_px"].get<double>(),
                cam["label_sigma_sd_px"].get<double>(), cam["label_sigma_a_priori_px"].get<double>(),
                cam["label_sigma_source"].get<std::string>().c_str());
    EXPECT_EQ(cam["label_sigma_a_priori_px"].get<double>(), 1.0);
    EXPECT_GT(cam["label_sigma_px"].get<double>(), 0.1) << id;
    EXPECT_LT(cam["label_sigma_px"].get<double>(), 0.26) << id;
    EXPECT_EQ(cam["label_sigma_source"].get<std::string>().rfind("estimated from the views", 0), 0u) << id;
  }
  const auto summary = nlohmann::json::parse(test::read_text(dir / "out" / "trajectory.json"));
  EXPECT_EQ(summary["settings"]["label_sigma"]["mode"], "estimate");
}

TEST(TrajectoryCli, BadImportedCalibrationsNameTheirCause) {
  const fs::path dir = test::scratch_dir("trajectory_cli_imported_bad");
  const nlohmann::json good = imported_mission(dir);
  const auto run = [&](const nlohmann::json& j) {
    test::write_text(dir / "bad.json", j.dump());
    return test::run_cli("track '" + (dir / "bad.json").string() + "'");
  };
  // A good run first: a later failed one must not leave its trajectory.csv as if it were its own.
  ASSERT_EQ(run(good).exit_code, 0);
  ASSERT_TRUE(fs::exists(dir / "out" / "trajectory.csv"));
  // A σ not stated: the calibration would be taken as exact.
  nlohmann::json j = good;
  j["trajectory"]["imported_cameras"][0]["sigma"].erase("rotation_mrad");
  auto r = run(j);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("trajectory.imported_cameras[0].sigma.rotation_mrad"), std::string::npos) << r.err;
  // Both files, or neither.
  j = good;
  j["trajectory"]["imported_cameras"][0]["calibration"]["dlt"] = (dir / "dlt.csv").string();
  r = run(j);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("both 'opencv_yml' and 'dlt'"), std::string::npos) << r.err;
  j["trajectory"]["imported_cameras"][0]["calibration"] = nlohmann::json::object();
  r = run(j);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("no calibration file given"), std::string::npos) << r.err;
  // A DLT made for another image height: 500 px less moves its principal point (v0 410) off the image.
  j = good;
  j["trajectory"]["imported_cameras"][1]["sensor"]["height_px"] = 300;
  r = run(j);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("dlt.csv"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("lies off the 1280 × 300 image"), std::string::npos) << r.err;
  // A camera id the mission's cameras already use.
  j = good;
  j["cameras"] = mission(dir)["cameras"];
  j["trajectory"]["imported_cameras"][1]["id"] = "cam2";
  r = run(j);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("duplicate camera id 'cam2'"), std::string::npos) << r.err;
  // A DLT file one line short: the file and the count.
  std::string dlt = test::read_text(dir / "dlt.csv");
  test::write_text(dir / "short.csv", dlt.substr(0, dlt.rfind('\n', dlt.size() - 2) + 1));
  j = good;
  j["trajectory"]["imported_cameras"][1]["calibration"]["dlt"] = (dir / "short.csv").string();
  r = run(j);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("short.csv"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("10 coefficient lines"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "trajectory.csv"));  // the stage removed the old one first
  // A calibration.json of another site: its pose is in another ENU frame.
  write_rangecal_json(test::range_camera_at("lab_c", {5, -70, 2}, drone(1.5)), {45.6, 122.9, 150.0},
                      dir / "elsewhere.json");
  j = good;
  j["trajectory"]["imported_cameras"][2]["calibration"]["rangecal_json"] = (dir / "elsewhere.json").string();
  r = run(j);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("elsewhere.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("world_frame"), std::string::npos) << r.err;
  // This mission's own output imported: its camera would count twice.
  fs::create_directories(dir / "out" / "lab_c");
  fs::copy_file(dir / "lab_c.json", dir / "out" / "lab_c" / "calibration.json",
                fs::copy_options::overwrite_existing);
  j = good;
  j["trajectory"]["imported_cameras"][2]["calibration"]["rangecal_json"] =
      (dir / "out" / "lab_c" / "calibration.json").string();
  r = run(j);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("this mission's own output"), std::string::npos) << r.err;
  // A σ stated beside a calibration.json's own covariance.
  j = good;
  j["trajectory"]["imported_cameras"][2]["sigma"] = good["trajectory"]["imported_cameras"][0]["sigma"];
  r = run(j);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("states its own covariance"), std::string::npos) << r.err;
  // An OpenCV file of another image size.
  j = good;
  j["trajectory"]["imported_cameras"][0]["sensor"]["width_px"] = 1920;
  r = run(j);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("lab_a.yml"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("1280 × 800"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "trajectory.csv"));
}

}  // namespace
}  // namespace rangecal
