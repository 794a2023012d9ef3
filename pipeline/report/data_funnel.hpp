#pragma once
// What each stage took in, kept and dropped, and why (report.html "Data funnel"), from the counts
// the stages recorded in run.json (`stages.<name>.counts`, read with each stage's record reader in
// pipeline/io/, docs/outputs.md). A stage that did not run or recorded no counts (it failed), a
// camera it did not record, or an intersection skipped gives no row: the funnel shows what was
// recorded, nothing guessed. A count of the wrong type throws rangecal::Error naming its field.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace rangecal {

struct FunnelDrop {
  std::string reason;  ///< a few words ("Q = 2", "offset > align.max_frame_offset_s")
  long long count = 0;
};

struct FunnelRow {
  std::string stage;   ///< gnss, align, detect, calibrate, intersect
  std::string camera;  ///< camera id; empty for mission-wide stages
  std::string unit;    ///< what is counted: epochs, frames, observations, poles
  long long in = 0;
  long long kept = 0;
  std::vector<FunnelDrop> dropped;  ///< non-zero reasons only, in the stage's order
};

/// The funnel rows in stage order (gnss; align, detect, calibrate per camera in `camera_ids`
/// order; intersect), from run.json's `stages` object (may be null or lack stages).
std::vector<FunnelRow> data_funnel(const nlohmann::json& stages, const std::vector<std::string>& camera_ids);

}  // namespace rangecal
