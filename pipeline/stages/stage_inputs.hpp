#pragma once
// What the stages share when reading their inputs: the check that an earlier stage's output is
// there, with a message that says which stage to run; a calibrated camera for triangulation.
#include <optional>
#include <string>
#include <vector>

#include "pipeline/mission/mission_config.hpp"
#include "vision/camera/calibration_result.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

/// Throws rangecal::Error (input) naming `path` when it is missing: "run the <stage> stage first".
void require_stage_output(const std::string& path, const char* stage);

/// A camera's calibration as the stages that triangulate with it take it (intersect, trajectory).
struct CalibratedCamera {
  CalibrationResult result;
  CameraCovariance covariance;  ///< empty when the result has none usable
  bool usable = false;          ///< the covariance is usable
};

/// Reads `<out>/<id>/calibration.json`. Missing: nullopt and a warning in `warnings` (one
/// uncalibrated camera, e.g. one whose calibration failed, must not stop the others). Without a
/// usable covariance: a warning that the σ then counts `sigma_without` only for this camera. Errors
/// in the file are input errors naming it.
std::optional<CalibratedCamera> read_calibrated_camera(const MissionConfig& cfg, const std::string& id,
                                                       const std::string& sigma_without,
                                                       std::vector<std::string>* warnings);

}  // namespace rangecal
