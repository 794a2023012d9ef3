#pragma once
// The one table of a mission's stages: each stage's name and which files it writes
// (pipeline/io/output_paths.hpp names them), in the order they run. A stage removes its own
// previous outputs and those of every later stage before it runs, so that a file in the output
// folder is always the product of the latest run of its stage over the current inputs, never an old
// result passed off as new (docs/reliability.md, "Outputs on failure"). The function that runs each
// stage is bound to its row in pipeline/stages/mission_runner.cpp: the stages sit above this
// library, which must not include them (docs/architecture.md "Where to add … a stage").
#include <string>
#include <vector>

#include "pipeline/mission/mission_config.hpp"

namespace rangecal {

/// A stage as the files know it: its name (its command `rangecal <name>` and its section of
/// run.json) and every file it may write for a config (paths under cfg.output_dir).
struct MissionStage {
  std::string name;
  std::vector<std::string> (*outputs)(const MissionConfig& cfg);
};

/// The stages of a mission in order, one row each: gnss, align, detect, calibrate, intersect,
/// report.
const std::vector<MissionStage>& mission_stage_table();

/// The names of mission_stage_table(), in order.
const std::vector<std::string>& mission_stage_names();

/// Every file `stage` may write for `cfg` (paths under cfg.output_dir), including each
/// calibration_<method>.json of any method. Throws (usage) for an unknown stage name.
std::vector<std::string> stage_output_files(const MissionConfig& cfg, const std::string& stage);

/// Removes the files of `stage` and of every later stage that exist; returns the removed paths.
/// Throws (input) naming a file that exists but cannot be removed.
std::vector<std::string> remove_outputs_from_stage(const MissionConfig& cfg, const std::string& stage);

}  // namespace rangecal
