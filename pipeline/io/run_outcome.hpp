#pragma once
// The outcome of a mission's output folder (docs/reliability.md "Run outcome"): what a batch job
// reads instead of guessing from warnings. Complete (exit 0) when every stage that ran succeeded
// and none recorded a shortfall; partial (exit 4) when a stage finished but could not deliver
// what a complete mission needs — a configured camera not calibrated, an intersection check
// without the poles it needs, a poorly determined parameter under run.fail_on_poorly_determined
// — its outputs kept and marked; degraded (exit 0) when it is complete but a stage recorded a
// degradation — figures it delivered that the user should look at before trusting them; failed (the
// error's exit code) when a stage threw.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/mission/mission_config.hpp"

namespace rangecal {

struct RunOutcome {
  std::string status = "complete";  ///< complete | degraded | partial | failed
  int exit_code = 0;                ///< 0 complete or degraded, 4 partial, the stage error's code when failed
  std::vector<std::string> reasons;  ///< "<stage>: <what is missing or degraded>", in stage order
};

/// The outcome of run.json's stage sections (`stages.<name>.status`, `.error.exit_code`,
/// `.shortfalls`, `.degradations`), in mission order, leaving out `before_stage` and the stages after it (all
/// when empty).
RunOutcome run_outcome(const nlohmann::json& run_json, const std::string& before_stage = "");

/// {"status", "exit_code", "reasons"}: run.json's and summary.json's `outcome`.
nlohmann::json run_outcome_json(const RunOutcome& outcome);

/// run_outcome of <output_dir>/run.json (complete when the file is missing or unreadable).
RunOutcome read_run_outcome(const MissionConfig& cfg, const std::string& before_stage = "");

/// The reasons joined with "; " (for the console and error messages).
std::string outcome_reasons_text(const RunOutcome& outcome);

}  // namespace rangecal
