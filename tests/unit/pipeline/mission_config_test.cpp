// Mission config loader (docs/config.md): the full example, defaults, path resolution, and one test per
// error class, each asserting the message names the config file and the JSON path.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>

#include "config/error.hpp"
#include "config/sha256.hpp"
#include "pipeline/io/network_json.hpp"
#include "pipeline/mission/mission_config.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {
namespace fs = std::filesystem;

const std::string kExample = (test::source_dir() / "config/examples/mission_full.json").string();

std::string example_text() {
  return test::read_text(kExample);
}

// A minimal valid config (required keys only).
nlohmann::json minimal() {
  return nlohmann::json::parse(R"({
    "site": {"origin": {"lat": 45.6, "lon": 122.8, "h": 150.0}},
    "gnss": {"pos_files": ["gnss/rover.pos"]},
    "lever_arm": {"vertical_m": 0.25},
    "cameras": [{"id": "cam1", "sensor": {"width_px": 1280, "height_px": 800, "pixel_size_um": [20, 20]},
                 "lens": {"nominal_focal_mm": 135}}]
  })");
}

const std::string kPath = "/missions/m1/mission.json";

// Parses `j` (no file checks) and expects a usage error whose field starts with `json_path` and
// whose message contains `words`.
void expect_error(const nlohmann::json& j, const std::string& json_path, const std::string& words) {
  try {
    parse_mission_config(j.dump(), kPath, false);
    FAIL() << "expected an error at " << json_path;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_EQ(e.exit_code(), 2);
    EXPECT_EQ(e.file(), kPath);
    EXPECT_EQ(e.field().rfind(json_path, 0), 0u) << "field '" << e.field() << "' vs " << json_path;
    const std::string msg = e.what();
    EXPECT_NE(msg.find(kPath), std::string::npos) << msg;
    EXPECT_NE(msg.find(json_path), std::string::npos) << msg;
    EXPECT_NE(msg.find(words), std::string::npos) << msg;
  }
}

TEST(MissionConfig, FullExampleParses) {
  const MissionConfig c = parse_mission_config(example_text(), kExample, false);
  const fs::path dir = fs::path(kExample).lexically_normal().parent_path();
  EXPECT_EQ(c.config_dir, dir.string());
  EXPECT_EQ(c.config_sha256, sha256_hex(example_text()));
  EXPECT_NE(c.mission.find("Range 3"), std::string::npos);
  EXPECT_DOUBLE_EQ(c.origin.lat_deg, 45.6);
  EXPECT_DOUBLE_EQ(c.origin.lon_deg, 122.8);
  EXPECT_DOUBLE_EQ(c.origin.h_m, 150.0);
  ASSERT_EQ(c.gnss.pos_files.size(), 2u);
  EXPECT_EQ(c.gnss.pos_files[0], (dir / "gnss/rover.pos").string());
  EXPECT_EQ(c.gnss.accept_quality, (std::vector<int>{1, 2}));
  EXPECT_DOUBLE_EQ(c.gnss.max_sd_m, 0.05);
  EXPECT_DOUBLE_EQ(c.gnss.max_gap_s, 0.5);
  EXPECT_EQ(c.attitude_file, (dir / "gnss/attitude.csv").string());
  EXPECT_EQ(c.lever_arm.kind, LeverArmConfig::Kind::body_frd);
  EXPECT_EQ(c.lever_arm.body_frd_m, Eigen::Vector3d(0, 0, 0.25));
  EXPECT_EQ(c.poles_file, (dir / "survey/poles.csv").string());
  ASSERT_EQ(c.cameras.size(), 2u);
  const CameraConfig& a = c.cameras[0];
  EXPECT_EQ(a.id, "cam1");
  EXPECT_EQ(a.frames.timestamps, (dir / "cam1/timestamps.csv").string());
  EXPECT_TRUE(a.frames.allow_missing);
  EXPECT_EQ(a.sensor.width_px, 1280);
  EXPECT_EQ(a.sensor.height_px, 800);
  EXPECT_DOUBLE_EQ(a.sensor.pixel_size_um[0], 20.0);
  EXPECT_DOUBLE_EQ(a.nominal_focal_mm, 135.0);
  EXPECT_EQ(a.pole_observations, (dir / "cam1/poles_px.csv").string());
  ASSERT_TRUE(a.priors.principal_point_px.has_value());
  EXPECT_EQ(*a.priors.principal_point_px, Eigen::Vector2d(640, 400));
  EXPECT_EQ(*a.priors.center_enu_m, Eigen::Vector3d(0, 0, 1.5));
  EXPECT_DOUBLE_EQ(a.priors.center_sigma_m, 0.05);
  EXPECT_EQ(c.cameras[1].frames.cine, (dir / "cam2/run42.cine").string());
  EXPECT_TRUE(c.cameras[1].frames.timestamps.empty());
  EXPECT_FALSE(c.cameras[1].priors.principal_point_px.has_value());
  EXPECT_DOUBLE_EQ(c.align.max_frame_offset_s, 0.005);
  EXPECT_DOUBLE_EQ(c.detect.min_snr, 12);
  EXPECT_EQ(c.detect.threads, 2);
  EXPECT_EQ(c.calibrate.method, "bundle");
  EXPECT_EQ(c.calibrate.free, (std::vector<std::string>{"f", "k1", "pose"}));
  EXPECT_EQ(c.calibrate.compare, (std::vector<std::string>{"tsai", "tsai_sassa", "dlt_lmqn"}));
  EXPECT_TRUE(c.calibrate.use_control_poles);
  EXPECT_EQ(c.calibrate.seed, 7u);
  EXPECT_DOUBLE_EQ(c.intersect.pick_sigma_px, 0.4);
  EXPECT_DOUBLE_EQ(c.intersect.bar_mean_dR_m, 0.015);
  EXPECT_FALSE(c.run.fail_on_poorly_determined);
  EXPECT_EQ(c.output_dir, (dir / "out").string());
}

TEST(MissionConfig, DefaultsOfOptionalKeys) {
  const MissionConfig c = parse_mission_config(minimal().dump(), kPath, false);
  EXPECT_EQ(c.mission, "");
  EXPECT_EQ(c.gnss.accept_quality, std::vector<int>{1});
  EXPECT_DOUBLE_EQ(c.gnss.max_sd_m, 0.05);
  EXPECT_DOUBLE_EQ(c.gnss.max_gap_s, 0.5);
  EXPECT_TRUE(c.attitude_file.empty());
  EXPECT_EQ(c.lever_arm.kind, LeverArmConfig::Kind::vertical);
  EXPECT_DOUBLE_EQ(c.lever_arm.vertical_m, 0.25);
  EXPECT_TRUE(c.poles_file.empty());
  EXPECT_TRUE(c.cameras[0].frames.timestamps.empty());
  EXPECT_FALSE(c.cameras[0].frames.allow_missing);
  EXPECT_DOUBLE_EQ(c.cameras[0].priors.principal_point_sigma_px, 30);
  EXPECT_DOUBLE_EQ(c.align.max_frame_offset_s, 0.005);
  EXPECT_DOUBLE_EQ(c.detect.min_snr, 10);
  EXPECT_EQ(c.detect.threads, 0);
  // Not given: the calibrate stage chooses (network when cameras share epochs, else bundle).
  EXPECT_EQ(c.calibrate.method, "");
  EXPECT_DOUBLE_EQ(c.calibrate.control_sigma_m, 0.005);
  // The principal point free under its prior by default (docs/config.md "The principal point").
  EXPECT_EQ(c.calibrate.free, (std::vector<std::string>{"f", "k1", "u0", "v0", "pose"}));
  EXPECT_TRUE(c.calibrate.compare.empty());
  EXPECT_EQ(c.calibrate.free_candidates, (std::vector<std::string>{"k2"}));
  EXPECT_FALSE(c.calibrate.use_control_poles);
  EXPECT_EQ(c.calibrate.seed, 1u);
  EXPECT_EQ(c.output_dir, "/missions/m1/out");
}

TEST(MissionConfig, AbsolutePathsAreUsedAsGiven) {
  auto j = minimal();
  j["gnss"]["pos_files"] = {"/data/ppk/a.pos"};
  j["output_dir"] = "/results/run7";
  const MissionConfig c = parse_mission_config(j.dump(), kPath, false);
  EXPECT_EQ(c.gnss.pos_files[0], "/data/ppk/a.pos");
  EXPECT_EQ(c.output_dir, "/results/run7");
}

TEST(MissionConfig, LoadsFromDiskWithFilesPresentAndRelativeToConfigFolder) {
  const fs::path dir = test::scratch_dir("mission_config_load");
  test::write_text(dir / "m/gnss/rover.pos", "% empty\n");
  const std::string text = minimal().dump();
  test::write_text(dir / "m/mission.json", text);
  const MissionConfig c = load_mission_config((dir / "m/mission.json").string());
  EXPECT_EQ(c.gnss.pos_files[0], (dir / "m/gnss/rover.pos").string());
  EXPECT_EQ(c.config_sha256, sha256_hex(text));
}

// ---- error classes -------------------------------------------------------------------------

TEST(MissionConfigErrors, InvalidJsonNamesLine) {
  try {
    parse_mission_config("{\n \"mission\": \"x\",\n \"site\": }\n", kPath, false);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find(kPath + ":3"), std::string::npos) << e.what();
  }
}

// Found by fuzzing (docs/reliability.md "Fuzzing"): a number beyond the range of a double made the
// JSON library throw its out_of_range, which escaped as a foreign exception.
TEST(MissionConfigErrors, NumberOutOfDoubleRangeNamesLine) {
  try {
    parse_mission_config("{\n \"mission\": \"x\",\n \"site\": 11e308\n}\n", kPath, false);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_EQ(e.file(), kPath);
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find(kPath + ":3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("11e308"), std::string::npos) << e.what();
    EXPECT_EQ(e.field(), "site");  // the key path, as the other config errors name it
  }
}

TEST(MissionConfigErrors, UnknownTopLevelKeySuggests) {
  auto j = minimal();
  j["calibrat"] = nlohmann::json::object();
  expect_error(j, "calibrat", "did you mean 'calibrate'?");
}

TEST(MissionConfigErrors, UnknownNestedKeySuggests) {
  auto j = minimal();
  j["cameras"][0]["sensor"]["pixel_size_mu"] = {20, 20};
  expect_error(j, "cameras[0].sensor.pixel_size_mu", "did you mean 'pixel_size_um'?");
}

TEST(MissionConfigErrors, UnknownKeyFarFromAnyHasNoSuggestion) {
  auto j = minimal();
  j["gnss"]["zzzzzz"] = 1;
  try {
    parse_mission_config(j.dump(), kPath, false);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "gnss.zzzzzz");
    EXPECT_EQ(std::string(e.what()).find("did you mean"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("'max_gap_s'"), std::string::npos);  // lists what is allowed
  }
}

TEST(MissionConfigErrors, WrongTypeNamesExpectedForm) {
  auto j = minimal();
  j["cameras"].push_back(j["cameras"][0]);
  j["cameras"][1]["id"] = "cam2";
  j["cameras"][1]["sensor"]["pixel_size_um"] = "20";
  expect_error(j, "cameras[1].sensor.pixel_size_um", "expected an array of 2 positive numbers (µm)");
}

TEST(MissionConfigErrors, WrongArrayLength) {
  auto j = minimal();
  j["cameras"][0]["sensor"]["pixel_size_um"] = {20, 20, 20};
  expect_error(j, "cameras[0].sensor.pixel_size_um", "got an array of 3 elements");
}

TEST(MissionConfigErrors, MissingRequiredKey) {
  auto j = minimal();
  j["cameras"][0]["sensor"].erase("height_px");
  expect_error(j, "cameras[0].sensor.height_px", "missing required key");
  auto k = minimal();
  k.erase("site");
  expect_error(k, "site", "missing required key");
}

TEST(MissionConfigErrors, LatitudeOutOfRange) {
  auto j = minimal();
  j["site"]["origin"]["lat"] = 95.0;
  expect_error(j, "site.origin.lat", "[-90, 90]");
}

TEST(MissionConfigErrors, NegativePixelSize) {
  auto j = minimal();
  j["cameras"][0]["sensor"]["pixel_size_um"] = {20, -20};
  expect_error(j, "cameras[0].sensor.pixel_size_um", "positive");
}

TEST(MissionConfigErrors, NonPositiveImageWidth) {
  auto j = minimal();
  j["cameras"][0]["sensor"]["width_px"] = 0;
  expect_error(j, "cameras[0].sensor.width_px", "positive integer");
  j["cameras"][0]["sensor"]["width_px"] = 1280.5;
  expect_error(j, "cameras[0].sensor.width_px", "positive integer");
}

TEST(MissionConfigErrors, AcceptQualityOutsideOneToSix) {
  auto j = minimal();
  j["gnss"]["accept_quality"] = {1, 7};
  expect_error(j, "gnss.accept_quality[1]", "1-6");
}

TEST(MissionConfigErrors, DuplicateCameraIds) {
  auto j = minimal();
  j["cameras"].push_back(j["cameras"][0]);
  expect_error(j, "cameras[1].id", "duplicate camera id 'cam1'");
}

TEST(MissionConfigErrors, BadCameraIdCharacters) {
  auto j = minimal();
  j["cameras"][0]["id"] = "cam 1/x";
  expect_error(j, "cameras[0].id", "letters, digits");
}

TEST(MissionConfigErrors, ReservedCameraIdsAreRefused) {
  for (const char* id : {"gnss", "network", "method_choice"}) {
    auto j = minimal();
    j["cameras"][0]["id"] = id;
    expect_error(j, "cameras[0].id", "'" + std::string(id) + "' is reserved");
  }
  // A reserved name inside a longer id is an ordinary id.
  auto j = minimal();
  j["cameras"][0]["id"] = "network_2";
  EXPECT_EQ(parse_mission_config(j.dump(), kPath, false).cameras[0].id, "network_2");
}

TEST(MissionConfigErrors, UnknownMethodSuggests) {
  auto j = minimal();
  j["calibrate"] = {{"method", "bundel"}};
  expect_error(j, "calibrate.method", "did you mean 'bundle'?");
}

TEST(MissionConfig, ControlPoleSigmaIsReadAndMustBePositive) {
  auto j = minimal();
  j["calibrate"] = {{"control_sigma_m", 0.02}};
  EXPECT_DOUBLE_EQ(parse_mission_config(j.dump(), kPath, false).calibrate.control_sigma_m, 0.02);
  j["calibrate"] = {{"control_sigma_m", 0}};
  expect_error(j, "calibrate.control_sigma_m", "positive standard deviation");
}

TEST(MissionConfig, AccuracyBarIsReadAndRangeChecked) {
  auto j = minimal();
  EXPECT_DOUBLE_EQ(parse_mission_config(j.dump(), kPath, false).intersect.bar_mean_dR_m, 0.010);
  j["intersect"] = {{"bar_mean_dR_m", 0.025}};
  EXPECT_DOUBLE_EQ(parse_mission_config(j.dump(), kPath, false).intersect.bar_mean_dR_m, 0.025);
  j["intersect"] = {{"bar_mean_dR_m", 0}};
  expect_error(j, "intersect.bar_mean_dR_m", "positive distance in metres");
  j["intersect"] = {{"bar_mean_dR_m", 10}};  // 10 mm written as metres
  expect_error(j, "intersect.bar_mean_dR_m", "at most 1");
  j["intersect"] = {{"bar_mean_dR_m", "1 cm"}};
  expect_error(j, "intersect.bar_mean_dR_m", "positive distance in metres");
}

// docs/reliability.md "Run outcome": poorly determined parameters are warnings unless asked.
TEST(MissionConfig, FailOnPoorlyDeterminedIsABooleanOffByDefault) {
  auto j = minimal();
  EXPECT_FALSE(parse_mission_config(j.dump(), kPath, false).run.fail_on_poorly_determined);
  j["run"] = {{"fail_on_poorly_determined", true}};
  EXPECT_TRUE(parse_mission_config(j.dump(), kPath, false).run.fail_on_poorly_determined);
  j["run"] = {{"fail_on_poorly_determined", "yes"}};
  expect_error(j, "run.fail_on_poorly_determined", "true or false");
  j["run"] = {{"fail_on_poorly_determind", true}};
  expect_error(j, "run.fail_on_poorly_determind", "did you mean 'fail_on_poorly_determined'");
}

TEST(MissionConfig, FailOnDegradedIsABooleanOffByDefault) {
  auto j = minimal();
  EXPECT_FALSE(parse_mission_config(j.dump(), kPath, false).run.fail_on_degraded);
  j["run"] = {{"fail_on_degraded", true}};
  EXPECT_TRUE(parse_mission_config(j.dump(), kPath, false).run.fail_on_degraded);
  j["run"] = {{"fail_on_degraded", 1}};
  expect_error(j, "run.fail_on_degraded", "true or false");
}

// docs/config.md: each camera's a-priori pixel σ per kind of observation, and whether the network
// estimates the centroids'.
TEST(MissionConfig, PixelSigmaPerCameraAndSource) {
  auto j = minimal();
  const MissionConfig d = parse_mission_config(j.dump(), kPath, false);
  EXPECT_DOUBLE_EQ(d.cameras[0].pixel_sigma.centroid_px, 0.1);
  EXPECT_DOUBLE_EQ(d.cameras[0].pixel_sigma.pick_px, 0.3);
  EXPECT_TRUE(d.calibrate.estimate_image_sigma);
  EXPECT_TRUE(d.calibrate.image_time_correlation);
  j["calibrate"] = {{"image_sigma", "estimate_independent"}};
  const MissionConfig e = parse_mission_config(j.dump(), kPath, false);
  EXPECT_TRUE(e.calibrate.estimate_image_sigma);
  EXPECT_FALSE(e.calibrate.image_time_correlation);
  j["cameras"][0]["pixel_sigma_px"] = {{"centroid", 1.5}};
  j["calibrate"] = {{"image_sigma", "stated"}};
  const MissionConfig c = parse_mission_config(j.dump(), kPath, false);
  EXPECT_DOUBLE_EQ(c.cameras[0].pixel_sigma.centroid_px, 1.5);
  EXPECT_DOUBLE_EQ(c.cameras[0].pixel_sigma.pick_px, 0.3);
  EXPECT_FALSE(c.calibrate.estimate_image_sigma);
  j["cameras"][0]["pixel_sigma_px"] = {{"pick", 0}};
  expect_error(j, "cameras[0].pixel_sigma_px.pick", "positive standard deviation in pixels");
  j["cameras"][0]["pixel_sigma_px"] = {{"centroid", 250}};  // a pixel count, not a σ
  expect_error(j, "cameras[0].pixel_sigma_px.centroid", "at most 100");
  j["cameras"][0]["pixel_sigma_px"] = {{"centriod", 1}};
  expect_error(j, "cameras[0].pixel_sigma_px.centriod", "did you mean 'centroid'");
  j["cameras"][0].erase("pixel_sigma_px");
  j["calibrate"] = {{"image_sigma", "estimated"}};
  expect_error(j, "calibrate.image_sigma", "\"estimate\", \"estimate_independent\" or \"stated\"");
}

TEST(MissionConfigErrors, UnknownCompareMethod) {
  auto j = minimal();
  j["calibrate"] = {{"compare", {"tsai", "zhang"}}};
  expect_error(j, "calibrate.compare[1]", "unknown method 'zhang'");
}

TEST(MissionConfigErrors, UnknownFreeParameterSuggests) {
  auto j = minimal();
  j["calibrate"] = {{"free", {"f", "kl"}}};
  expect_error(j, "calibrate.free[1]", "did you mean 'k1'?");
  j["calibrate"] = {{"free", {"f", "clock_ofset"}}};
  expect_error(j, "calibrate.free[1]", "did you mean 'clock_offset'?");
}

TEST(MissionConfigErrors, FreeCandidatesAreFreeParameterNames) {
  auto j = minimal();
  j["calibrate"] = {{"free_candidates", {"k2", "k4"}}};
  expect_error(j, "calibrate.free_candidates[1]", "unknown parameter 'k4'");
  j["calibrate"] = {{"free_candidates", {"k2", "k2"}}};
  expect_error(j, "calibrate.free_candidates[1]", "listed twice");
  j["calibrate"] = {{"free_candidates", {"k2", "pose"}}};
  expect_error(j, "calibrate.free_candidates[1]", "'pose' is a group of parameters");
  j["calibrate"] = {{"free_candidates", "k2"}};
  expect_error(j, "calibrate.free_candidates", "array of distinct parameter names");
  j["calibrate"] = {{"free_candidates", {"k2", "p1", "p2"}}};
  const MissionConfig cfg = parse_mission_config(j.dump(), kPath, false);
  EXPECT_EQ(cfg.calibrate.free_candidates, (std::vector<std::string>{"k2", "p1", "p2"}));
  j["calibrate"] = {{"free_candidates", nlohmann::json::array()}};
  EXPECT_TRUE(parse_mission_config(j.dump(), kPath, false).calibrate.free_candidates.empty());
}

TEST(MissionConfig, ACameraMayHaveItsOwnFreeSet) {
  auto j = minimal();
  j["cameras"][0]["free"] = {"f", "k1", "k2", "u0", "v0", "pose"};
  const MissionConfig cfg = parse_mission_config(j.dump(), kPath, false);
  EXPECT_EQ(cfg.cameras[0].free, (std::vector<std::string>{"f", "k1", "k2", "u0", "v0", "pose"}));
  EXPECT_EQ(cfg.calibrate.free, default_calibrate_free());
  j["cameras"][0]["free"] = {"f", "k4"};
  expect_error(j, "cameras[0].free[1]", "unknown parameter 'k4'");
  j["cameras"][0]["free"] = nlohmann::json::array();
  expect_error(j, "cameras[0].free", "non-empty array");
}

TEST(MissionConfig, ClockOffsetIsAFreeParameter) {
  auto j = minimal();
  j["calibrate"] = {{"free", {"f", "k1", "pose", "clock_offset"}}};
  const MissionConfig cfg = parse_mission_config(j.dump(), kPath, false);
  EXPECT_EQ(cfg.calibrate.free.back(), "clock_offset");
}

TEST(MissionConfigErrors, EmptyPosFiles) {
  auto j = minimal();
  j["gnss"]["pos_files"] = nlohmann::json::array();
  expect_error(j, "gnss.pos_files", "non-empty array");
}

TEST(MissionConfigErrors, LeverArmBodyWithoutAttitude) {
  auto j = minimal();
  j["lever_arm"] = {{"body_frd_m", {0, 0, 0.25}}};
  expect_error(j, "lever_arm.body_frd_m", "needs the UAV attitude");
}

TEST(MissionConfigErrors, LeverArmTwoForms) {
  auto j = minimal();
  j["lever_arm"] = {{"vertical_m", 0.25}, {"total_station", "lever.csv"}};
  expect_error(j, "lever_arm", "exactly one of");
}

TEST(MissionConfigErrors, FramesBothTimestampsAndCine) {
  auto j = minimal();
  j["cameras"][0]["frames"] = {{"timestamps", "t.csv"}, {"cine", "a.cine"}};
  expect_error(j, "cameras[0].frames", "both 'timestamps' and 'cine'");
}

TEST(MissionConfigErrors, PrincipalPointPriorOutsideImage) {
  auto j = minimal();
  j["cameras"][0]["priors"] = {{"principal_point_px", {1500, 400}}};
  expect_error(j, "cameras[0].priors.principal_point_px", "outside the 1280x800 image");
}

TEST(MissionConfigErrors, ControlPolesWithoutPolesFile) {
  auto j = minimal();
  j["calibrate"] = {{"use_control_poles", true}};
  expect_error(j, "calibrate.use_control_poles", "no \"poles\" file");
}

TEST(MissionConfigErrors, MissingReferencedFileNamesKey) {
  const fs::path dir = test::scratch_dir("mission_config_missing_file");
  auto j = minimal();
  test::write_text(dir / "gnss/rover.pos", "% x\n");
  j["attitude"] = {{"file", "gnss/attitude.csv"}};
  const std::string path = (dir / "mission.json").string();
  test::write_text(path, j.dump());
  try {
    load_mission_config(path);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_EQ(e.field(), "attitude.file");
    EXPECT_NE(std::string(e.what()).find((dir / "gnss/attitude.csv").string()), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("file not found"), std::string::npos);
  }
}

TEST(MissionConfigErrors, MissingConfigFile) {
  try {
    load_mission_config("/nonexistent/mission.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_EQ(e.file(), "/nonexistent/mission.json");
  }
}

TEST(MissionConfigErrors, TopLevelNotAnObject) {
  try {
    parse_mission_config("[1, 2]", kPath, false);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("expected a mission config object"), std::string::npos) << e.what();
  }
}

TEST(MissionConfig, PpkErrorModelDefaultsToEstimateAndParsesBothForms) {
  // No key: estimated from the mission, its robust first solve under the white model.
  const GnssConfig by_default = parse_mission_config(minimal().dump(), kPath, false).gnss;
  EXPECT_TRUE(by_default.estimate_error_model);
  EXPECT_FALSE(by_default.error_model.correlated());
  nlohmann::json j = minimal();
  j["gnss"]["error_model"] = nlohmann::json::parse(R"({"white_scale": {"horizontal": 0.35, "vertical": 0.34},
      "gauss_markov": {"sd_m": {"horizontal": 0.008, "vertical": 0.014}, "tau_s": 30}})");
  const PpkErrorModel m = parse_mission_config(j.dump(), kPath, false).gnss.error_model;
  EXPECT_TRUE(m.correlated());
  EXPECT_FALSE(parse_mission_config(j.dump(), kPath, false).gnss.estimate_error_model);
  EXPECT_DOUBLE_EQ(m.white_scale_h, 0.35);
  EXPECT_DOUBLE_EQ(m.white_scale_v, 0.34);
  EXPECT_DOUBLE_EQ(m.gm_sd_h_m, 0.008);
  EXPECT_DOUBLE_EQ(m.gm_sd_v_m, 0.014);
  EXPECT_DOUBLE_EQ(m.tau_h_s, 30);
  EXPECT_DOUBLE_EQ(m.tau_v_s, 30);
  // A white scale alone: white, scaled.
  j["gnss"]["error_model"] = nlohmann::json::parse(R"({"white_scale": 1.5})");
  const PpkErrorModel w = parse_mission_config(j.dump(), kPath, false).gnss.error_model;
  EXPECT_FALSE(w.correlated());
  EXPECT_DOUBLE_EQ(w.white_scale_h, 1.5);
  EXPECT_DOUBLE_EQ(w.white_scale_v, 1.5);
  // Estimated from the mission, or white by name.
  j["gnss"]["error_model"] = "estimate";
  EXPECT_TRUE(parse_mission_config(j.dump(), kPath, false).gnss.estimate_error_model);
  j["gnss"]["error_model"] = "white";
  const GnssConfig named = parse_mission_config(j.dump(), kPath, false).gnss;
  EXPECT_FALSE(named.estimate_error_model);
  EXPECT_FALSE(named.error_model.correlated());
  EXPECT_DOUBLE_EQ(named.error_model.white_scale_h, 1);
}

TEST(MissionConfig, PpkErrorModelPastedFromNetworkJsonIsTheModelItStates) {
  // network.json's statistics.ppk_error_model as the network writes it (gnss/track/ppk_error_model_json
  // and the estimate beside it), pasted into the next mission's gnss.error_model.
  PpkErrorEstimate e;
  e.model = {0.35, 0.33, 0.008, 0.014, 27, 120};
  e.sd = {0.02, 0.03, 0.001, 0.002, 9, std::nan("")};
  e.record_s = 143;
  nlohmann::json written = ppk_error_model_json(e.model, 240);
  written["gauss_markov"]["independent_looks"] = {{"horizontal", 5.3}, {"vertical", 1.2}};
  written["estimate"] = ppk_error_estimate_json(e);
  nlohmann::json j = minimal();
  j["gnss"]["error_model"] = nlohmann::json::parse(written.dump());
  const GnssConfig g = parse_mission_config(j.dump(), kPath, false).gnss;
  EXPECT_FALSE(g.estimate_error_model);
  EXPECT_DOUBLE_EQ(g.error_model.white_scale_h, 0.35);
  EXPECT_DOUBLE_EQ(g.error_model.white_scale_v, 0.33);
  EXPECT_DOUBLE_EQ(g.error_model.gm_sd_h_m, 0.008);
  EXPECT_DOUBLE_EQ(g.error_model.gm_sd_v_m, 0.014);
  EXPECT_DOUBLE_EQ(g.error_model.tau_h_s, 27);
  EXPECT_DOUBLE_EQ(g.error_model.tau_v_s, 120);
  // The same file read back by the report's reader gives the same model.
  const PpkErrorModelRecord r =
      parse_ppk_error_model_json(written, "network.json", "statistics.ppk_error_model");
  EXPECT_DOUBLE_EQ(r.model.tau_v_s, g.error_model.tau_v_s);
  EXPECT_DOUBLE_EQ(r.model.gm_sd_h_m, g.error_model.gm_sd_h_m);
  EXPECT_DOUBLE_EQ(r.looks_h, 5.3);
  EXPECT_EQ(r.states, 240);
  // An estimate on its upper bound is exp(log bound), one rounding step above it: still read.
  j["gnss"]["error_model"] =
      ppk_error_model_json(PpkErrorModel{std::exp(std::log(kMaxWhiteScale)), 1, 0, 0, 0, 0}, 0);
  EXPECT_NEAR(parse_mission_config(j.dump(), kPath, false).gnss.error_model.white_scale_h, kMaxWhiteScale,
              1e-12);
  // A white model as written (gauss_markov null) is the white model.
  j["gnss"]["error_model"] = ppk_error_model_json(PpkErrorModel{0.8, 0.9, 0, 0, 0, 0}, 0);
  const PpkErrorModel w = parse_mission_config(j.dump(), kPath, false).gnss.error_model;
  EXPECT_FALSE(w.correlated());
  EXPECT_DOUBLE_EQ(w.white_scale_h, 0.8);
  EXPECT_DOUBLE_EQ(w.white_scale_v, 0.9);
}

TEST(MissionConfigErrors, PpkErrorModelOutOfRangeOrHalfGiven) {
  const auto with = [](const char* model) {
    nlohmann::json j = minimal();
    j["gnss"]["error_model"] = nlohmann::json::parse(model);
    return j;
  };
  expect_error(with(R"({"white_scale": 0})"), "gnss.error_model.white_scale", "a number in (0, 10]");
  expect_error(with(R"({"white_scale": {"horizontal": 0.3}})"), "gnss.error_model.white_scale",
               "missing required key");
  expect_error(with(R"({"gauss_markov": {"sd_m": 0.01}})"), "gnss.error_model.gauss_markov",
               "missing required key");
  expect_error(with(R"({"gauss_markov": {"sd_m": 2, "tau_s": 30}})"), "gnss.error_model.gauss_markov.sd_m",
               "[0, 1] m");
  expect_error(with(R"({"gauss_markov": {"sd_m": 0.01, "tau_s": 0}})"), "gnss.error_model.gauss_markov.tau_s",
               "(0, 100000] s");
  expect_error(with(R"({"gauss_markov": {"sd_m": {"horizontal": 0.01, "vertical": 0}, "tau_s": 30}})"),
               "gnss.error_model.gauss_markov.sd_m", "one axis only");
  expect_error(with(R"({"gauss_markov": {"sd_m": 0.01, "tau_s": 30, "tau": 5}})"),
               "gnss.error_model.gauss_markov", "tau");
  expect_error(with(R"({"white_scale": "half"})"), "gnss.error_model.white_scale", "horizontal");
  expect_error(with(R"("estimated")"), "gnss.error_model", "\"estimate\", \"white\" or an object");
}

}  // namespace
}  // namespace rangecal

namespace rangecal {
namespace {

// cameras[i].track (docs/config.md "Imported tracks").
nlohmann::json with_track(const nlohmann::json& track) {
  nlohmann::json j = minimal();
  j["cameras"][0]["track"] = track;
  return j;
}

TEST(MissionConfig, ImportedTrackParses) {
  const nlohmann::json j = with_track({{"file", "cam1/xypts.csv"},
                                       {"camera", 2},
                                       {"y_origin", "bottom"},
                                       {"t0_utc", "2026-05-04T10:00:00Z"},
                                       {"fps", 29.97},
                                       {"t0_frame", 1},
                                       {"clock", "estimate"},
                                       {"clock_search_s", {-100, 100}}});
  const MissionConfig c = parse_mission_config(j.dump(), kPath, false);
  ASSERT_TRUE(c.cameras[0].track);
  const TrackConfig& t = *c.cameras[0].track;
  EXPECT_EQ(t.file, "/missions/m1/cam1/xypts.csv");
  EXPECT_EQ(t.read.camera, 2);
  EXPECT_EQ(t.read.point, 1);
  EXPECT_EQ(t.read.y_origin, TrackReadOptions::YOrigin::bottom);
  EXPECT_EQ(t.read.width_px, 1280);
  EXPECT_DOUBLE_EQ(t.fps, 29.97);
  EXPECT_EQ(t.t0_frame, 1);
  EXPECT_TRUE(t.estimate_clock);
  EXPECT_DOUBLE_EQ(t.clock_search_s->second, 100);
  EXPECT_DOUBLE_EQ(c.cameras[0].pixel_sigma.track_px, 1.0);
}

TEST(MissionConfig, ImportedTrackErrors) {
  nlohmann::json both = with_track({{"file", "t.csv"}, {"timestamps", "ts.csv"}});
  both["cameras"][0]["frames"] = {{"timestamps", "cam1/ts.csv"}};
  expect_error(both, "cameras[0].track", "not both");
  expect_error(with_track({{"file", "t.csv"}}), "cameras[0].track", "times are not given");
  expect_error(with_track({{"file", "t.csv"}, {"timestamps", "a.csv"}, {"fps", 30}}), "cameras[0].track",
               "both");
  expect_error(with_track({{"file", "t.csv"}, {"timestamps", "a.csv"}, {"y_origin", "up"}}),
               "cameras[0].track.y_origin", "DLTdv8");
  expect_error(with_track({{"file", "t.csv"}, {"timestamps", "a.csv"}, {"format", "dlt"}}),
               "cameras[0].track.format", "unknown track format");
  expect_error(with_track({{"file", "t.csv"}, {"t0_utc", "yesterday"}, {"fps", 30}}),
               "cameras[0].track.t0_utc", "ISO 8601");
  expect_error(with_track({{"file", "t.csv"}, {"timestamps", "a.csv"}, {"clock_search_s", {0, 10}}}),
               "cameras[0].track.clock_search_s", "estimate");
  expect_error(with_track({{"file", "t.csv"}, {"timestamps", "a.csv"}, {"clock", "gps"}}),
               "cameras[0].track.clock", "time_code");
}

}  // namespace
}  // namespace rangecal

namespace rangecal {
namespace {

TEST(MissionConfig, TrackReadout) {
  nlohmann::json j = minimal();
  j["cameras"][0]["track"] = {{"file", "t.csv"}, {"timestamps", "a.csv"}, {"readout_s", 0.021}};
  EXPECT_DOUBLE_EQ(parse_mission_config(j.dump(), kPath, false).cameras[0].track->readout_s, 0.021);
  j["cameras"][0]["track"]["readout_s"] = "estimate";
  expect_error(j, "cameras[0].track.readout_s", "needs");
  j["cameras"][0]["track"]["clock"] = "estimate";
  EXPECT_TRUE(parse_mission_config(j.dump(), kPath, false).cameras[0].track->estimate_readout);
  j["cameras"][0]["track"]["readout_s"] = 0.5;
  expect_error(j, "cameras[0].track.readout_s", "±0.1");
}

}  // namespace
}  // namespace rangecal

namespace rangecal {
namespace {

// cameras[i].target_track and trajectory (docs/trajectory.md): the track keys, with "clock"
// "time_code" or "calibration" and "timing_sigma_s".
TEST(MissionConfig, TargetTrack) {
  nlohmann::json j = minimal();
  j["cameras"][0]["target_track"] = {
      {"file", "cam1/target.csv"}, {"timestamps", "cam1/ts.csv"}, {"timing_sigma_s", 0.0005}};
  j["trajectory"] = {{"rate_hz", 100}};
  MissionConfig c = parse_mission_config(j.dump(), kPath, false);
  EXPECT_DOUBLE_EQ(c.trajectory.extrapolation_sigma_px_per_px, 0.05);  // the default
  j["trajectory"]["extrapolation_sigma_px_per_px"] = 0;
  c = parse_mission_config(j.dump(), kPath, false);
  EXPECT_DOUBLE_EQ(c.trajectory.extrapolation_sigma_px_per_px, 0);
  EXPECT_FALSE(c.trajectory.smooth);  // the default
  j["trajectory"]["smoothing"] = "constant_acceleration";
  c = parse_mission_config(j.dump(), kPath, false);
  EXPECT_TRUE(c.trajectory.smooth);
  EXPECT_FALSE(c.trajectory.estimate_label_sigma);  // the default: "stated"
  j["trajectory"]["label_sigma"] = "estimate";
  c = parse_mission_config(j.dump(), kPath, false);
  EXPECT_TRUE(c.trajectory.estimate_label_sigma);
  j["trajectory"]["label_sigma"] = "stated";
  c = parse_mission_config(j.dump(), kPath, false);
  EXPECT_FALSE(c.trajectory.estimate_label_sigma);
  ASSERT_TRUE(c.cameras[0].target_track);
  EXPECT_EQ(c.cameras[0].target_track->file, "/missions/m1/cam1/target.csv");
  EXPECT_DOUBLE_EQ(c.cameras[0].target_track->timing_sigma_s, 0.0005);
  EXPECT_FALSE(c.cameras[0].target_track->calibration_clock);
  EXPECT_DOUBLE_EQ(c.trajectory.rate_hz, 100);
  // "calibration": the clock the align stage estimates from the camera's own track.
  j["cameras"][0]["target_track"]["clock"] = "calibration";
  expect_error(j, "cameras[0].target_track.clock", "this camera has none");
  j["cameras"][0].erase("frames");
  j["cameras"][0]["track"] = {{"file", "t.csv"}, {"timestamps", "a.csv"}, {"clock", "estimate"}};
  c = parse_mission_config(j.dump(), kPath, false);
  EXPECT_TRUE(c.cameras[0].target_track->calibration_clock);
  EXPECT_FALSE(c.cameras[0].target_track->estimate_clock);
}

TEST(MissionConfig, TargetTrackErrors) {
  nlohmann::json j = minimal();
  j["cameras"][0]["target_track"] = {{"file", "t.csv"}, {"timestamps", "a.csv"}, {"clock", "estimate"}};
  expect_error(j, "cameras[0].target_track.clock", "calibration");
  j["cameras"][0]["target_track"] = {{"file", "t.csv"}, {"timestamps", "a.csv"}, {"clock_search_s", {0, 1}}};
  expect_error(j, "cameras[0].target_track", "clock_search_s");
  j["cameras"][0]["target_track"] = {{"file", "t.csv"}, {"timestamps", "a.csv"}, {"timing_sigma_s", 2}};
  expect_error(j, "cameras[0].target_track.timing_sigma_s", "0 to 1");
  j["cameras"][0]["target_track"] = {{"file", "t.csv"}, {"timestamps", "a.csv"}, {"readout_s", "estimate"}};
  expect_error(j, "cameras[0].target_track.readout_s", "needs");
  j["cameras"][0].erase("target_track");
  j["trajectory"] = {{"rate_hz", 0}};
  expect_error(j, "trajectory.rate_hz", "positive");
  j["trajectory"] = {{"rate", 5}};
  expect_error(j, "trajectory", "rate");
  j["trajectory"] = {{"extrapolation_sigma_px_per_px", 2}};
  expect_error(j, "trajectory.extrapolation_sigma_px_per_px", "from 0 to 1");
  j["trajectory"] = {{"smoothing", "spline"}};
  expect_error(j, "trajectory.smoothing", "constant_acceleration");
  j["trajectory"] = {{"label_sigma", "estimated"}};
  expect_error(j, "trajectory.label_sigma", "\"estimate\" or \"stated\"");
  j["trajectory"] = {{"extrapolation_sigma_px_per_px", -0.1}};
  expect_error(j, "trajectory.extrapolation_sigma_px_per_px", "from 0 to 1");
}

// trajectory.imported_cameras (docs/trajectory.md "Imported calibrations"): a camera calibrated
// elsewhere, every σ stated.
nlohmann::json imported() {
  return {
      {"id", "lab1"},
      {"calibration", {{"dlt", "lab/dlt.csv"}, {"column", 2}}},
      {"sensor", {{"width_px", 1920}, {"height_px", 1080}, {"pixel_size_um", {5.5, 5.5}}}},
      {"sigma", {{"focal_px", 3}, {"principal_point_px", 2}, {"position_m", 0.02}, {"rotation_mrad", 0.1}}},
      {"target_track", {{"file", "lab/t.csv"}, {"t0_utc", "2026-05-04T10:00:00Z"}, {"fps", 30}}}};
}

TEST(MissionConfig, ImportedCameras) {
  nlohmann::json j = minimal();
  j["trajectory"]["imported_cameras"] = {imported()};
  MissionConfig c = parse_mission_config(j.dump(), kPath, false);
  ASSERT_EQ(c.trajectory.imported_cameras.size(), 1u);
  const ImportedCameraConfig& ic = c.trajectory.imported_cameras[0];
  EXPECT_EQ(ic.id, "lab1");
  EXPECT_EQ(ic.dlt, "/missions/m1/lab/dlt.csv");
  EXPECT_TRUE(ic.opencv_yml.empty());
  EXPECT_EQ(ic.dlt_column, 2);
  EXPECT_DOUBLE_EQ(ic.sigma.focal_px, 3);
  EXPECT_DOUBLE_EQ(ic.sigma.rotation_mrad, 0.1);
  EXPECT_DOUBLE_EQ(ic.sigma.image_px, 0);  // the default
  EXPECT_DOUBLE_EQ(ic.label_sigma_px, 1);  // the default
  EXPECT_EQ(ic.sensor.height_px, 1080);
  EXPECT_EQ(ic.target_track.file, "/missions/m1/lab/t.csv");
  EXPECT_FALSE(ic.target_track.calibration_clock);
  // Another mission's calibration.json: its own covariance, no σ stated.
  nlohmann::json cam = imported();
  cam["calibration"] = {{"rangecal_json", "lab/calibration.json"}};
  cam.erase("sigma");
  j["trajectory"]["imported_cameras"] = {cam};
  c = parse_mission_config(j.dump(), kPath, false);
  EXPECT_EQ(c.trajectory.imported_cameras[0].rangecal_json, "/missions/m1/lab/calibration.json");
  EXPECT_DOUBLE_EQ(c.trajectory.imported_cameras[0].sigma.focal_px, 0);
}

TEST(MissionConfig, ImportedCameraErrors) {
  nlohmann::json j = minimal();
  const auto with = [&](const std::function<void(nlohmann::json&)>& change) {
    nlohmann::json cam = imported();
    change(cam);
    j["trajectory"]["imported_cameras"] = {cam};
    return j;
  };
  const std::string at = "trajectory.imported_cameras[0]";
  expect_error(with([](nlohmann::json& c) { c["sigma"].erase("position_m"); }), at + ".sigma.position_m",
               "metres");
  expect_error(with([](nlohmann::json& c) { c["sigma"]["focal_px"] = -1; }), at + ".sigma.focal_px",
               "0 to 10000");
  expect_error(with([](nlohmann::json& c) { c["sigma"]["image_px"] = 101; }), at + ".sigma.image_px",
               "0 to 100");
  expect_error(with([](nlohmann::json& c) { c.erase("sigma"); }), at + ".sigma", "stated 1σ");
  expect_error(with([](nlohmann::json& c) { c["calibration"]["opencv_yml"] = "a.yml"; }), at + ".calibration",
               "both 'opencv_yml' and 'dlt'");
  expect_error(with([](nlohmann::json& c) { c["calibration"] = nlohmann::json::object(); }),
               at + ".calibration", "no calibration file");
  expect_error(with([](nlohmann::json& c) {
                 c["calibration"] = {{"rangecal_json", "c.json"}};
               }),
               at + ".sigma", "states its own covariance");
  expect_error(with([](nlohmann::json& c) {
                 c["calibration"] = {{"rangecal_json", "c.json"}, {"opencv_yml", "a.yml"}, {"dlt", "d.csv"}};
               }),
               at + ".calibration", "all of 'opencv_yml', 'dlt' and 'rangecal_json'");
  expect_error(with([](nlohmann::json& c) {
                 c["calibration"] = {{"opencv_yml", "a.yml"}, {"column", 1}};
               }),
               at + ".calibration.column", "only with");
  expect_error(with([](nlohmann::json& c) { c["calibration"]["column"] = 0; }), at + ".calibration.column",
               "1 to 1000");
  expect_error(with([](nlohmann::json& c) { c["target_track"]["clock"] = "calibration"; }),
               at + ".target_track.clock", "UTC");
  expect_error(with([](nlohmann::json& c) { c["label_sigma_px"] = 200; }), at + ".label_sigma_px",
               "at most 100");
  expect_error(with([](nlohmann::json& c) { c["id"] = "cam1"; }), at + ".id", "duplicate camera id 'cam1'");
  expect_error(with([](nlohmann::json& c) { c.erase("target_track"); }), at + ".target_track", "2-D track");
  expect_error(with([](nlohmann::json& c) { c["lens"] = 1; }), at, "lens");
  j = minimal();
  j["trajectory"]["imported_cameras"] = {imported(), imported()};
  expect_error(j, "trajectory.imported_cameras[1].id", "duplicate camera id 'lab1'");
}

}  // namespace
}  // namespace rangecal
