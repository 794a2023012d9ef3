#pragma once
// The trajectory stage (docs/trajectory.md, docs/outputs.md): each camera's `target_track` (2-D labels
// of the target with their frame times), its `<out>/<cam>/calibration.json`, the network's joint
// covariance and image σ (network.json) and, for a target track on the camera's estimated clock, the
// align stage's clock (run.json) → `<out>/trajectory.csv` and counts in run.json.
#include "pipeline/io/run_log.hpp"
#include "pipeline/mission/mission_config.hpp"

namespace rangecal {

/// Throws rangecal::Error (input, exit 3) naming `cameras[].target_track` when no camera has one:
/// `rangecal trajectory CONFIG` asked for a stage with nothing to do.
void require_trajectory_inputs(const MissionConfig& cfg);

/// Runs the stage. Without any target track it does nothing (run.json says why: a mission need not
/// have a target). A camera with a target track but no calibration.json is skipped with a warning; a
/// trajectory with fewer than two calibrated cameras is a shortfall. Errors in the files (tracks,
/// times, calibration.json, network.json, run.json's clock) are input errors naming file, line and
/// field.
StageLog run_trajectory_stage(const MissionConfig& cfg);

}  // namespace rangecal
