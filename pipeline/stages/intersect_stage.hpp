#pragma once
// The intersect stage (docs/intersection.md, docs/outputs.md): each camera's `<out>/<cam>/calibration.json`
// and its `pole_observations` picks, with the pole survey, → `<out>/intersection.csv` (check poles; seed 002
// Table 4) and counts in run.json. Behaviour and warnings: docs/intersection.md.
#include "pipeline/io/run_log.hpp"
#include "pipeline/mission/mission_config.hpp"

namespace rangecal {

/// Throws rangecal::Error (input, exit 3) naming the config key when the mission gives the stage
/// nothing to do: no `poles` survey, or no camera with `pole_observations`. Used by
/// `rangecal intersect CONFIG`, where asking for the stage without its inputs is a mistake; the
/// full run instead skips the stage with a warning (run_intersect_stage).
void require_intersect_inputs(const MissionConfig& cfg);

/// Runs the stage. Without a pole survey or without any camera's picks it does nothing and returns
/// a log with the warning "no poles: intersection skipped" (a mission need not have poles). A
/// camera with picks but no calibration.json is skipped with a warning; when no camera with picks
/// is calibrated it throws (input) naming the missing files. Errors in the files themselves
/// (survey, picks, calibration.json) are input errors naming file, line and field.
StageLog run_intersect_stage(const MissionConfig& cfg);

}  // namespace rangecal
