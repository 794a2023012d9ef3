// The calibrate stage's record (run.json stages.calibrate.counts, docs/outputs.md): written and read
// back field for field, camera ids apart from the mission-level keys, and a malformed value named
// by its field.
#include "pipeline/io/calibrate_record.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "config/error.hpp"

namespace rangecal {
namespace {

CalibrateRecord example() {
  CalibrateRecord r;
  CalibrateCameraRecord& a = r.cameras["cam1"];
  a.pairs = 73;
  a.control_poles = 6;
  a.method = "network";
  a.rms_px = 0.125;
  a.n_used = 77;
  a.n_rejected = 2;
  a.opencv_fit_max_px = 0.0021;
  a.opencv_undistort_max_px = 0.0034;
  a.dlt_only_rms_px = 1.5;
  a.dlt_only_max_px = 4.25;
  a.dlt_profile_max_px = 0.03;
  a.method_time_s = {{"bundle", 0.1234}, {"tsai", 0.0021}};
  a.warnings = {{CalibrationWarningKind::correlated, "cam1", {CameraParameter::f, CameraParameter::CU}},
                {CalibrationWarningKind::variance_factor, "cam1", {}}};
  CalibrateCameraRecord& b = r.cameras["cam2"];
  b.pairs = 12;
  b.control_poles = 0;
  b.failed = "points on one line";
  // A camera named like a mission-level key stays a camera.
  r.cameras["method_choice_cam"].method = "bundle";
  r.network = {{"variance_factor", 1.02}, {"dof", 400}};
  r.method_choice = MethodChoiceRecord{"network", 71, "default: 71 epochs seen by two or more cameras"};
  return r;
}

TEST(CalibrateRecord, RoundTripsEveryField) {
  const CalibrateRecord r = example();
  const nlohmann::json j = calibrate_record_json(r);
  // Through the text, as run.json holds it.
  const CalibrateRecord back =
      parse_calibrate_record(nlohmann::json::parse(j.dump(2)), "run.json", "stages.calibrate.counts");
  ASSERT_EQ(back.cameras.size(), 3u);
  const CalibrateCameraRecord& a = back.cameras.at("cam1");
  EXPECT_EQ(a.pairs, 73u);
  EXPECT_EQ(a.control_poles, 6u);
  EXPECT_TRUE(a.failed.empty());
  EXPECT_EQ(a.method, "network");
  EXPECT_EQ(a.rms_px, 0.125);
  EXPECT_EQ(a.n_used, 77);
  EXPECT_EQ(a.n_rejected, 2);
  EXPECT_EQ(a.opencv_fit_max_px, 0.0021);
  EXPECT_EQ(a.opencv_undistort_max_px, 0.0034);
  EXPECT_EQ(a.dlt_only_rms_px, 1.5);
  EXPECT_EQ(a.dlt_only_max_px, 4.25);
  EXPECT_EQ(a.dlt_profile_max_px, 0.03);
  EXPECT_EQ(a.method_time_s, (std::map<std::string, double>{{"bundle", 0.1234}, {"tsai", 0.0021}}));
  ASSERT_EQ(a.warnings.size(), 2u);
  EXPECT_EQ(a.warnings[0].kind, CalibrationWarningKind::correlated);
  EXPECT_EQ(a.warnings[0].camera, "cam1");
  EXPECT_EQ(a.warnings[0].parameters,
            (std::vector<CameraParameter>{CameraParameter::f, CameraParameter::CU}));
  EXPECT_EQ(a.warnings[1].kind, CalibrationWarningKind::variance_factor);
  EXPECT_TRUE(a.warnings[1].parameters.empty());
  const CalibrateCameraRecord& b = back.cameras.at("cam2");
  EXPECT_EQ(b.pairs, 12u);
  EXPECT_EQ(b.failed, "points on one line");
  EXPECT_TRUE(b.method.empty());
  EXPECT_EQ(back.network, r.network);
  ASSERT_TRUE(back.method_choice);
  EXPECT_EQ(back.method_choice->method, "network");
  EXPECT_EQ(back.method_choice->shared_epochs, 71u);
  EXPECT_EQ(back.method_choice->why, r.method_choice->why);
  // Written again, the same text.
  EXPECT_EQ(calibrate_record_json(back).dump(2), j.dump(2));
}

TEST(CalibrateRecord, CamerasLiveApartFromTheMissionKeys) {
  const nlohmann::json j = calibrate_record_json(example());
  EXPECT_EQ(j.size(), 3u);  // cameras, network, method_choice
  EXPECT_EQ(j["cameras"].size(), 3u);
  EXPECT_EQ(j["cameras"]["cam2"],
            (nlohmann::json{{"pairs", 12}, {"control_poles", 0}, {"failed", "points on one line"}}));
  EXPECT_EQ(j["method_choice"]["shared_epochs"], 71);
  // Without the network: neither key.
  CalibrateRecord r;
  r.cameras["c1"].method = "bundle";
  const nlohmann::json k = calibrate_record_json(r);
  EXPECT_FALSE(k.contains("network"));
  EXPECT_FALSE(k.contains("method_choice"));
}

TEST(CalibrateRecord, WarningCodesAreWrittenByNameAndAnUnknownKindIsNamed) {
  nlohmann::json j = calibrate_record_json(example());
  EXPECT_EQ(j["cameras"]["cam1"]["warnings"][0],
            (nlohmann::json{{"kind", "correlated"}, {"camera", "cam1"}, {"parameters", {"f", "CU"}}}));
  EXPECT_EQ(j["cameras"]["cam1"]["warnings"][1],
            (nlohmann::json{
                {"kind", "variance_factor"}, {"camera", "cam1"}, {"parameters", nlohmann::json::array()}}));
  // Every kind's name reads back as that kind.
  for (int k = 0; k <= static_cast<int>(CalibrationWarningKind::clock_offset_not_estimated); ++k) {
    const auto kind = static_cast<CalibrationWarningKind>(k);
    EXPECT_EQ(warning_kind_from_name(warning_kind_name(kind)), kind) << warning_kind_name(kind);
  }
  j["cameras"]["cam1"]["warnings"][1]["kind"] = "correlated_somewhat";
  try {
    parse_calibrate_record(j, "/out/run.json", "stages.calibrate.counts");
    FAIL() << "an unknown kind was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "stages.calibrate.counts.cameras.cam1.warnings[1].kind");
  }
}

TEST(CalibrateRecord, NoResidualIsNullAndReadsBackAsNaN) {
  CalibrateRecord r;
  r.cameras["c1"].method = "bundle";  // rms_px NaN: no observation used
  const nlohmann::json j = nlohmann::json::parse(calibrate_record_json(r).dump());
  EXPECT_TRUE(j["cameras"]["c1"]["rms_px"].is_null());
  EXPECT_TRUE(std::isnan(parse_calibrate_record(j, "run.json", "counts").cameras.at("c1").rms_px));
}

TEST(CalibrateRecord, AWrongTypeNamesItsField) {
  nlohmann::json j = calibrate_record_json(example());
  j["cameras"]["cam1"]["n_used"] = "77";
  try {
    parse_calibrate_record(j, "/out/run.json", "stages.calibrate.counts");
    FAIL() << "a string count was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "/out/run.json");
    EXPECT_EQ(e.field(), "stages.calibrate.counts.cameras.cam1.n_used");
  }
}

}  // namespace
}  // namespace rangecal
