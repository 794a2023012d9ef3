#pragma once
// The camera centre's covariance (CalibrationResult::center_covariance_m2) of a method whose
// parameters include the centre form of the pose (CE, CN, CU; vision/camera/camera_parameters.hpp).
#include <Eigen/Core>

#include "vision/camera/calibration_result.hpp"

namespace rangecal {

/// The (CE, CN, CU) block of `result.covariance`: a held coordinate's rows and columns are zero;
/// NaN when the result has no covariance over its parameters.
Eigen::Matrix3d center_covariance(const CalibrationResult& result);

}  // namespace rangecal
