// The detect stage's record (run.json stages.detect.counts, docs/outputs.md): one object per
// camera, written and read back field for field, and a malformed value named by its camera and field.
#include "pipeline/io/detect_record.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "config/error.hpp"

namespace rangecal {
namespace {

DetectRecord example() {
  DetectRecord r;
  DetectCameraRecord& c = r.cameras["cam1"];
  c.time_source = "timestamps_csv";
  c.frames_examined = 139;
  c.by_status = {{"ok", 73}, {"no_blob", 60}, {"saturated", 6}};
  c.correspondences = 73;
  c.timestamp_check = TimestampCheckRecord{-18, 41.5, 0.75};
  DetectCameraRecord& d = r.cameras["cam2"];
  d.frames_examined = 5;
  d.by_status = {{"no_blob", 5}};
  return r;
}

TEST(DetectRecord, RoundTripsEveryField) {
  const DetectRecord r = example();
  const nlohmann::json j = detect_record_json(r);
  const DetectRecord back =
      parse_detect_record(nlohmann::json::parse(j.dump(2)), "run.json", "stages.detect.counts");
  ASSERT_EQ(back.cameras.size(), 2u);
  const DetectCameraRecord& c = back.cameras.at("cam1");
  EXPECT_EQ(c.time_source, "timestamps_csv");
  EXPECT_EQ(c.frames_examined, 139u);
  EXPECT_EQ(c.by_status, r.cameras.at("cam1").by_status);
  EXPECT_EQ(c.correspondences, 73u);
  ASSERT_TRUE(c.timestamp_check);
  EXPECT_EQ(c.timestamp_check->best_offset_s, -18);
  EXPECT_EQ(c.timestamp_check->rms_at_zero_px, 41.5);
  EXPECT_EQ(c.timestamp_check->rms_at_best_px, 0.75);
  EXPECT_FALSE(back.cameras.at("cam2").timestamp_check);
  EXPECT_EQ(detect_record_json(back).dump(2), j.dump(2));
}

TEST(DetectRecord, AnRmsNotComputedIsNullAndReadsBackAsNaN) {
  DetectRecord r = example();
  r.cameras["cam1"].timestamp_check->rms_at_best_px = std::nan("");
  const nlohmann::json j = nlohmann::json::parse(detect_record_json(r).dump());
  EXPECT_TRUE(j["cam1"]["timestamp_check"]["rms_at_best_px"].is_null());
  EXPECT_TRUE(std::isnan(
      parse_detect_record(j, "run.json", "counts").cameras.at("cam1").timestamp_check->rms_at_best_px));
}

TEST(DetectRecord, AWrongTypeNamesItsCameraAndField) {
  nlohmann::json j = detect_record_json(example());
  j["cam1"]["by_status"]["no_blob"] = 2.5;
  try {
    parse_detect_record(j, "/out/run.json", "stages.detect.counts");
    FAIL() << "a fractional count was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "/out/run.json");
    EXPECT_EQ(e.field(), "stages.detect.counts.cam1.by_status.no_blob");
  }
}

}  // namespace
}  // namespace rangecal
