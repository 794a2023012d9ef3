#pragma once
// The per-camera stages between the lamp track and the calibration (SPEC §4.2–4.3), each runnable
// alone from the files the previous stage wrote:
//   align   lamp_track.csv + the camera's frame list → <cam>/aligned.csv
//   detect  aligned.csv + the frames (only those decoded) → <cam>/detections.csv and the pairs
//           <cam>/correspondences.csv for the calibrate stage.
// A camera that yields nothing (no frame aligned, no lamp found) is reported with a warning and the
// other cameras go on; the stage fails (input error) only when no camera yields anything.
#include "config/mission_config.hpp"
#include "pipeline/io/run_log.hpp"

namespace rangecal {

StageLog run_align_stage(const MissionConfig& cfg);
StageLog run_detect_stage(const MissionConfig& cfg);

}  // namespace rangecal
