#pragma once
// Weighting of a pixel residual by its effective image covariance (docs/optimisation.md):
//   C = σ_px²·I + J_X·Σ_X·J_Xᵀ,   J_X = ∂pixel/∂world point,   W = L⁻¹ with L·Lᵀ = C,
// so the world-point noise (1 cm at 64 m through 135 mm / 20 µm ≈ 1 px) is counted honestly and
// W·(projected − observed) has unit covariance.
#include <Eigen/Core>
#include <vector>

#include "optim/bundle/bundle_observation.hpp"
#include "vision/camera/camera_model.hpp"

namespace rangecal {

/// ∂(u, v)/∂Xw (2×3, px/m) of `cam` at world point Xw (autodiff through the camera model).
Eigen::Matrix<double, 2, 3> pixel_jacobian_wrt_world(const Camera& cam, const Eigen::Vector3d& Xw);

/// W = L⁻¹, L the Cholesky factor of σ²·I + J_X·Σ_X·J_Xᵀ at `cam` (px⁻¹).
Eigen::Matrix2d whitening_matrix(const Camera& cam, const BundleObservation& o, double sigma_px);

/// whitening_matrix of every observation at `cam`, with its own σ_px when it gives one (> 0), else
/// `default_sigma_px`.
std::vector<Eigen::Matrix2d> whitening_matrices(const Camera& cam, const std::vector<BundleObservation>& obs,
                                                double default_sigma_px);

}  // namespace rangecal
