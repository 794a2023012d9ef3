// The run's outcome from run.json's stage sections (pipeline/io/run_outcome.hpp; docs/reliability.md
// "Run outcome"): complete, degraded (a degradation, exit 0), partial (a shortfall, exit 4) with its
// degradations listed after, failed (the stage error's code).
#include "pipeline/io/run_outcome.hpp"

#include <gtest/gtest.h>

namespace rangecal {
namespace {

nlohmann::json stages(const nlohmann::json& calibrate) {
  return {{"stages", {{"gnss", {{"status", "ok"}}}, {"calibrate", calibrate}}}};
}

TEST(RunOutcome, CompleteWithoutShortfallsOrDegradations) {
  const RunOutcome o = run_outcome(stages({{"status", "ok"}}));
  EXPECT_EQ(o.status, "complete");
  EXPECT_EQ(o.exit_code, 0);
  EXPECT_TRUE(o.reasons.empty());
}

TEST(RunOutcome, ADegradationMakesACompleteRunDegradedWithExitZero) {
  const RunOutcome o =
      run_outcome(stages({{"status", "ok"}, {"degradations", {"network variance factor 19.6: …"}}}));
  EXPECT_EQ(o.status, "degraded");
  EXPECT_EQ(o.exit_code, 0);
  ASSERT_EQ(o.reasons.size(), 1u);
  EXPECT_EQ(o.reasons[0], "calibrate: network variance factor 19.6: …");
  EXPECT_EQ(run_outcome_json(o)["status"], "degraded");
}

TEST(RunOutcome, APartialRunListsItsShortfallsThenItsDegradations) {
  const RunOutcome o = run_outcome(stages({{"status", "ok"},
                                           {"degradations", {"camera cam1: not written: camera_opencv.yml"}},
                                           {"shortfalls", {"camera cam2 not calibrated"}}}));
  EXPECT_EQ(o.status, "partial");
  EXPECT_EQ(o.exit_code, 4);
  ASSERT_EQ(o.reasons.size(), 2u);
  EXPECT_EQ(o.reasons[0], "calibrate: camera cam2 not calibrated");
  EXPECT_EQ(o.reasons[1], "calibrate: camera cam1: not written: camera_opencv.yml");
}

TEST(RunOutcome, AFailedStageKeepsItsExitCode) {
  const RunOutcome o = run_outcome(stages({{"status", "failed"},
                                           {"error", {{"exit_code", 3}, {"message", "bad file"}}},
                                           {"degradations", {"x"}}}));
  EXPECT_EQ(o.status, "failed");
  EXPECT_EQ(o.exit_code, 3);
}

}  // namespace
}  // namespace rangecal
