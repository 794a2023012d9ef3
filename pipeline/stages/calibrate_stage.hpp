#pragma once
// The calibrate stage (docs/optimisation.md): per camera, `<cam>/correspondences.csv` (+ `control` poles when
// calibrate.use_control_poles) → the configured method and every method in `compare`
// (pipeline/steps/calibration_methods.hpp); everything is computed first, then written:
// `<cam>/calibration.json`, `<cam>/camera_opencv.yml`, `<cam>/residuals.csv` (each pair's residual
// and whether it was used), and with `compare` `<cam>/methods.csv` and
// `<cam>/calibration_<method>.json`. A camera whose calibration fails is reported and the others go
// on; the stage fails only when no camera is calibrated.
#include "pipeline/io/run_log.hpp"
#include "pipeline/mission/mission_config.hpp"

namespace rangecal {

StageLog run_calibrate_stage(const MissionConfig& cfg);

}  // namespace rangecal
