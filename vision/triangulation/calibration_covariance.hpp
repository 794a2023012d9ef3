#pragma once
// A calibration result's parameter covariance in the form triangulation takes
// (vision/triangulation/triangulation.hpp's CameraCovariance).
#include "vision/camera/calibration_result.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

/// The covariance of `r` over its parameters; empty when the result has none (not computed, wrong
/// shape or non-finite), with `*usable` set to false then.
CameraCovariance camera_covariance(const CalibrationResult& r, bool* usable = nullptr);

}  // namespace rangecal
