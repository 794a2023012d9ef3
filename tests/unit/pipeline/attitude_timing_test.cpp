// The report's statement of an autopilot log's timing (pipeline/report/attitude_timing.hpp): read
// from run.json's gnss counts, and the sentence's figures.
#include "pipeline/report/attitude_timing.hpp"

#include <gtest/gtest.h>

#include "pipeline/io/gnss_record.hpp"

namespace rangecal {
namespace {

nlohmann::json stages_with(const GnssRecord& record) {
  return {{"gnss", {{"counts", gnss_record_json(record)}}}};
}

// A gnss record with an autopilot log put on UTC with `lag_ms` from `lag_source`.
GnssRecord with_log(const std::string& format, double lag_ms, const std::string& lag_source) {
  GnssRecord r;
  r.attitude.emplace().format = format;
  AutopilotLogRecord& log = r.attitude->log.emplace();
  log.gnss_lag_ms = lag_ms;
  log.gnss_lag_source = lag_source;
  return r;
}

TEST(AttitudeTiming, ReadsTheLagItsSourceAndTheLeverArmMotion) {
  GnssRecord r = with_log("dataflash", 120, "default for dataflash");
  r.lever_arm.source = "body_frd";
  r.lever_arm.motion_max_mm_per_ms = 0.1708;
  r.lever_arm.motion_rms_mm_per_ms = 0.0283;
  const std::optional<AttitudeTiming> t = attitude_timing(stages_with(r));
  ASSERT_TRUE(t);
  EXPECT_EQ(t->format, "dataflash");
  EXPECT_EQ(t->gnss_lag_ms, 120);
  EXPECT_EQ(t->lag_source, "default for dataflash");
  EXPECT_EQ(*t->motion_max_mm_per_ms, 0.1708);
  EXPECT_EQ(attitude_timing_sentence(*t),
            "Attitude: dataflash log put on UTC with a GNSS receiver lag of 120 ms (default for dataflash). "
            "Through the lever arm a timing error moves the lamp by up to 0.171 mm per ms (rms 0.028): "
            "10 ms of lag error, up to 1.7 mm.");
}

TEST(AttitudeTiming, NoneWithoutAnAutopilotLogAndNoMotionWithoutABodyLeverArm) {
  EXPECT_FALSE(attitude_timing(nlohmann::json()));
  GnssRecord csv;
  csv.attitude.emplace().format = "csv";
  csv.attitude->samples = 10;
  EXPECT_FALSE(attitude_timing(stages_with(csv)));
  GnssRecord r = with_log("ulog", 35, "attitude.gnss_lag_ms");
  r.lever_arm.source = "vertical";
  r.lever_arm.vertical_m = 0.25;
  const std::optional<AttitudeTiming> t = attitude_timing(stages_with(r));
  ASSERT_TRUE(t);
  EXPECT_FALSE(t->motion_max_mm_per_ms);
  EXPECT_EQ(attitude_timing_sentence(*t),
            "Attitude: ulog log put on UTC with a GNSS receiver lag of 35 ms (attitude.gnss_lag_ms).");
}

}  // namespace
}  // namespace rangecal
