#pragma once
// `rangecal run CONFIG` and `rangecal STAGE CONFIG` (docs/cli.md): the stages in order, each writing the
// files the next one reads (so any stage can be rerun alone), each timed here — the stages do not
// time themselves — and merged into run.json as it finishes.
#include <functional>
#include <string>
#include <vector>

#include "pipeline/io/run_log.hpp"
#include "pipeline/mission/mission_config.hpp"

namespace rangecal {

struct NamedStage {
  std::string name;
  std::function<StageLog(const MissionConfig&)> run;
};

/// The stages of a full run, in order: the rows of mission_stage_table() (gnss, align, detect,
/// calibrate, intersect, report; pipeline/io/stage_outputs.hpp), each with the function that runs
/// it. Throws std::logic_error when a row has no function or a function no row.
const std::vector<NamedStage>& mission_stages();

/// Runs the stage called `name` (one of mission_stages): removes temporary files left by dead
/// processes, removes this stage's previous outputs and every later stage's
/// (pipeline/io/stage_outputs.hpp), runs it, sets its wall time and merges its log into run.json.
/// A stage that throws has its error recorded in run.json (status "failed") and the error
/// propagates; the earlier stages' files and sections stay.
StageLog run_stage(const std::string& name, const MissionConfig& cfg);

/// Runs all stages in order; `on_stage_done` (may be empty) is called after each with its log.
/// Stops at the first stage that throws (its error propagates; the files of the stages before
/// stay valid).
std::vector<StageLog> run_mission(const MissionConfig& cfg,
                                  const std::function<void(const StageLog&)>& on_stage_done = {});

}  // namespace rangecal
