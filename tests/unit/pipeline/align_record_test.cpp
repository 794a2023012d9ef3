// The align stage's record (run.json stages.align.counts, docs/outputs.md): one object per camera,
// written and read back field for field, and a malformed value named by its camera and field.
#include "pipeline/io/align_record.hpp"

#include <gtest/gtest.h>

#include "config/error.hpp"

namespace rangecal {
namespace {

AlignRecord example() {
  AlignRecord r;
  AlignCameraRecord& c = r.cameras["cam1"];
  c.report = {3000, 150, 12, 144, 139, 3, 1, 1, -0.00012, 0.0011, 0.0049, 31.5, 0.154, 1234};
  c.time_source = "timestamps_csv";
  r.cameras["cam2"].time_source = "mraw_header";  // nothing aligned: the defaults
  return r;
}

TEST(AlignRecord, RoundTripsEveryField) {
  const AlignRecord r = example();
  const nlohmann::json j = align_record_json(r);
  const AlignRecord back =
      parse_align_record(nlohmann::json::parse(j.dump(2)), "run.json", "stages.align.counts");
  ASSERT_EQ(back.cameras.size(), 2u);
  const AlignCameraRecord& c = back.cameras.at("cam1");
  EXPECT_EQ(c.report.epochs, 3000u);
  EXPECT_EQ(c.report.frames_picked, 144u);
  EXPECT_EQ(c.report.frames_aligned, 139u);
  EXPECT_EQ(c.report.rejected_outside_track, 1u);
  EXPECT_EQ(c.report.mean_dt_s, -0.00012);
  EXPECT_EQ(c.report.worst_position_error_m, 0.154);
  EXPECT_EQ(c.report.worst_position_error_frame, 1234);
  EXPECT_EQ(c.time_source, "timestamps_csv");
  EXPECT_EQ(back.cameras.at("cam2").report.worst_position_error_frame, -1);
  EXPECT_EQ(align_record_json(back).dump(2), j.dump(2));
  // The camera ids are the keys.
  EXPECT_EQ(j.at("cam1").at("frames"), 150);
}

TEST(AlignRecord, AWrongTypeNamesItsCameraAndField) {
  nlohmann::json j = align_record_json(example());
  j["cam2"]["max_abs_dt_s"] = "0.004";
  try {
    parse_align_record(j, "/out/run.json", "stages.align.counts");
    FAIL() << "a string number was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "/out/run.json");
    EXPECT_EQ(e.field(), "stages.align.counts.cam2.max_abs_dt_s");
  }
}

}  // namespace
}  // namespace rangecal
