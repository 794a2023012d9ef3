#pragma once
// An independent check of the report's projection uncertainty (pipeline/report/projection_uncertainty.hpp):
// the 1σ pixel error of a world point's projection under a calibration's covariance, propagated by
// central differences of vision's project() rather than by the analytic Jacobian.
#include <Eigen/Core>

#include "vision/camera/calibration_result.hpp"

namespace rangecal::test {

/// √(largest eigenvalue of J·C·Jᵀ) (px), J = ∂project(X)/∂(r's free parameters) by central
/// differences (step 1e-4 σ of each), C = r.covariance. A projection that fails is a test failure
/// (and NaN).
double finite_difference_projection_sigma_px(const CalibrationResult& r, const Eigen::Vector3d& X);

}  // namespace rangecal::test
