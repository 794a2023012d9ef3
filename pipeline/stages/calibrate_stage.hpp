#pragma once
// The calibrate stage (SPEC §4.4): per camera, `<cam>/correspondences.csv` (+ `control` poles when
// calibrate.use_control_poles) → the configured method, and every method in `compare`; writes
// `<cam>/calibration.json`, `<cam>/camera_opencv.yml`, `<cam>/methods.csv` (with compare) and
// rewrites correspondences.csv with each pair's residual and whether it was used.
#include <string>
#include <vector>

#include "config/mission_config.hpp"
#include "pipeline/steps/calibration_methods.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/run_log.hpp"

namespace rangecal {

/// Noise model defaults used where the inputs carry no σ (docs/optimisation.md):
inline constexpr double kDefaultPixelSigmaPx = 0.1;  ///< lamp centroid σ (detector: ≤ 0.05 px RMS)
inline constexpr double kDefaultWorldSigmaM = 0.01;  ///< lamp position σ when correspondences lack sd
inline constexpr double kControlPoleSigmaM = 0.005;  ///< surveyed pole-top σ (total station / RTK)
inline constexpr double kPolePickSigmaPx = 0.3;      ///< a pole top picked by hand

/// Builds the calibration problem of one camera from its pairs and (optionally) control poles.
CalibrationProblem make_calibration_problem(const MissionConfig& cfg, const CameraConfig& cam,
                                            const std::vector<Correspondence>& pairs);

/// One row of methods.csv (seed 002 Table 1 layout), deterministic text.
std::string format_methods_csv(const std::vector<CalibrationResult>& results);

StageLog run_calibrate_stage(const MissionConfig& cfg);

}  // namespace rangecal
