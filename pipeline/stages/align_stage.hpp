#pragma once
// The align stage (docs/alignment.md): per camera, lamp_track.csv + the camera's frame list → the frames to
// use and the lamp at each one's exact UTC (pipeline/steps/align_frames.hpp) → <cam>/aligned.csv.
// A camera that aligns no frame is reported with a warning and the others go on; the stage fails
// (input error) only when no camera aligns anything.
#include "pipeline/io/run_log.hpp"
#include "pipeline/mission/mission_config.hpp"

namespace rangecal {

StageLog run_align_stage(const MissionConfig& cfg);

}  // namespace rangecal
