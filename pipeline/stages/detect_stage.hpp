#pragma once
// The detect stage (docs/frames_and_detection.md): per camera, aligned.csv + the frames (only those aligned
// are decoded) → the lamp in each frame (vision/detection/lamp_detector.hpp) → <cam>/detections.csv and the
// (lamp ENU, lamp pixel) pairs <cam>/correspondences.csv for the calibrate stage; and the check for
// whole-second errors in the frame time stamps (pipeline/steps/timestamp_check.hpp). A camera without a lamp
// is reported with a warning and the others go on; the stage fails (input error) only when no camera yields a
// pair.
#include "pipeline/io/run_log.hpp"
#include "pipeline/mission/mission_config.hpp"

namespace rangecal {

StageLog run_detect_stage(const MissionConfig& cfg);

}  // namespace rangecal
