#pragma once
// Which stage writes which file (pipeline/io/output_paths.hpp names them), so that a stage can
// remove its own previous outputs and those of every later stage before it runs: a file in the
// output folder is always the product of the latest run of its stage over the current inputs,
// never an old result passed off as new (docs/reliability.md, "Outputs on failure").
#include <string>
#include <vector>

#include "pipeline/mission/mission_config.hpp"

namespace rangecal {

/// The stages of a mission in order: gnss, align, detect, calibrate, intersect, report.
const std::vector<std::string>& mission_stage_names();

/// Every file `stage` may write for `cfg` (paths under cfg.output_dir), including each
/// calibration_<method>.json of any method. Throws (usage) for an unknown stage name.
std::vector<std::string> stage_output_files(const MissionConfig& cfg, const std::string& stage);

/// Removes the files of `stage` and of every later stage that exist; returns the removed paths.
/// Throws (input) naming a file that exists but cannot be removed.
std::vector<std::string> remove_outputs_from_stage(const MissionConfig& cfg, const std::string& stage);

}  // namespace rangecal
