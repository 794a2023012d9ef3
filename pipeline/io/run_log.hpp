#pragma once
// run.json (docs/outputs.md): versions, config hash, per-stage status, wall time, counts and warnings. Each
// stage can run alone, so each stage updates its own section of the file in the output folder
// (read, replace the section, drop the sections of the later stages — their outputs were removed
// with this stage's, pipeline/io/stage_outputs.hpp — write atomically). A stage that fails records
// its error in its section, and the file's top-level "status" says "failed" and which stage; its
// top-level "outcome" (pipeline/io/run_outcome.hpp) says whether the folder is a complete mission.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "config/error.hpp"
#include "pipeline/mission/mission_config.hpp"

namespace rangecal {

struct StageLog {
  std::string stage;  ///< gnss | align | detect | calibrate | intersect | report
  double wall_time_s = 0;
  nlohmann::json counts = nlohmann::json::object();  ///< stage-specific numbers (dropped epochs, …)
  std::vector<std::string> warnings;
  /// What the stage finished without but a complete mission needs (a camera not calibrated, an
  /// intersection check without poles): run.json's `shortfalls`, making the run's outcome partial
  /// (pipeline/io/run_outcome.hpp, exit 4) with the outputs kept.
  std::vector<std::string> shortfalls;
  /// What the stage delivered but a user should not trust without a look (a variance factor far
  /// above 1, an estimate on its bound, many PPK priors dropped, an export that cannot reproduce its
  /// camera): run.json's `degradations`, making a run that is otherwise complete `degraded`
  /// (pipeline/io/run_outcome.hpp, exit 0; 4 under run.fail_on_degraded).
  std::vector<std::string> degradations;
  bool failed = false;             ///< the stage threw: `error` says why, and it wrote no outputs
  nlohmann::json error = nullptr;  ///< {message, exit_code, file, line, field} when failed
  /// Previous outputs removed before the stage ran (its own and the later stages').
  std::vector<std::string> removed_outputs;
};

/// The section of a stage that failed with `e`.
StageLog failed_stage_log(const std::string& stage, const Error& e);

/// Merges `log` into <output_dir>/run.json (creating it), together with the program version, the
/// config path and its SHA-256 (also kept per stage: stages rerun alone may have run under
/// different configs). Drops the sections of the stages after log.stage. Wall times are rounded
/// to 1 ms. Sets the top-level `outcome` from the sections kept.
void update_run_log(const MissionConfig& cfg, const StageLog& log);

}  // namespace rangecal
