#pragma once
// run.json (SPEC §5): versions, config hash, per-stage wall time, counts and warnings. Each stage
// can run alone, so each stage updates its own section of the file in the output folder (read,
// replace the section, write atomically).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline/config/mission_config.hpp"

namespace rangecal {

struct StageLog {
  std::string stage;  ///< gnss | align | detect | calibrate | intersect | report
  double wall_time_s = 0;
  nlohmann::json counts = nlohmann::json::object();  ///< stage-specific numbers (dropped epochs, …)
  std::vector<std::string> warnings;
};

/// Merges `log` into <output_dir>/run.json (creating it), together with the program version, the
/// config path and its SHA-256. Wall times are rounded to 1 ms.
void update_run_log(const MissionConfig& cfg, const StageLog& log);

}  // namespace rangecal
