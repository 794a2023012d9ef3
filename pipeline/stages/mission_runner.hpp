#pragma once
// `rangecal run CONFIG` (SPEC §6): every stage in order, each writing the files the next one reads
// (so any stage can be rerun alone), each merged into run.json as it finishes.
#include <functional>
#include <string>
#include <vector>

#include "config/mission_config.hpp"
#include "pipeline/io/run_log.hpp"

namespace rangecal {

struct NamedStage {
  std::string name;
  std::function<StageLog(const MissionConfig&)> run;
};

/// The stages of a full run, in order.
const std::vector<NamedStage>& mission_stages();

/// Runs all stages; `on_stage_done` (may be empty) is called after each with its log. Stops at
/// the first stage that throws (its error propagates; the files of the stages before stay valid).
std::vector<StageLog> run_mission(const MissionConfig& cfg,
                                  const std::function<void(const StageLog&)>& on_stage_done = {});

}  // namespace rangecal
