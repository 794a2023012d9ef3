// The report's statement of an autopilot log's timing (pipeline/report/attitude_timing.hpp): read
// from run.json's gnss counts, and the sentence's figures.
#include "pipeline/report/attitude_timing.hpp"

#include <gtest/gtest.h>

namespace rangecal {
namespace {

nlohmann::json stages_with(const nlohmann::json& counts) {
  return {{"gnss", {{"counts", counts}}}};
}

TEST(AttitudeTiming, ReadsTheLagItsSourceAndTheLeverArmMotion) {
  const nlohmann::json stages = stages_with(
      {{"attitude",
        {{"format", "dataflash"}, {"gnss_lag_ms", 120}, {"gnss_lag_source", "default for dataflash"}}},
       {"lever_arm", {{"motion_max_mm_per_ms", 0.1708}, {"motion_rms_mm_per_ms", 0.0283}}}});
  const std::optional<AttitudeTiming> t = attitude_timing(stages);
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
  EXPECT_FALSE(attitude_timing(stages_with({{"attitude", {{"format", "csv"}, {"samples", 10}}}})));
  const std::optional<AttitudeTiming> t = attitude_timing(stages_with(
      {{"attitude", {{"format", "ulog"}, {"gnss_lag_ms", 35}, {"gnss_lag_source", "attitude.gnss_lag_ms"}}},
       {"lever_arm", {{"vertical_m", 0.25}}}}));
  ASSERT_TRUE(t);
  EXPECT_FALSE(t->motion_max_mm_per_ms);
  EXPECT_EQ(attitude_timing_sentence(*t),
            "Attitude: ulog log put on UTC with a GNSS receiver lag of 35 ms (attitude.gnss_lag_ms).");
}

}  // namespace
}  // namespace rangecal
