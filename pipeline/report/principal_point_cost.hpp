#pragma once
// What a principal point away from the value a calibration holds it at would cost the intersection
// through the flight volume (docs/accuracy_analysis.md "The principal point's default"), by linear
// propagation of the shift through each camera's calibration.
//
// Camera c is calibrated from its lamp pairs by minimising Σ_i e_iᵀ W_i e_i over its free parameters
// θ (e_i = π(θ, X̄_i) − u_i, W_i = (σ_px²·I + J_X,i·Σ_X,i·J_X,iᵀ)⁻¹, as the bundle weighs a fix). If
// its true principal point lies δ from the fixed value, the pixels are those of the truth and, to
// first order,
//     δθ = F⁻¹ Σ_i J_iᵀ W_i P_i δ,   F = Σ_i J_iᵀ W_i J_i,   P_i = ∂π/∂(u0, v0) at X̄_i,
// (the other parameters absorb what they can of the shift), and the estimated camera maps a world
// point X to a pixel off the true one by e(X) = K(X)·δθ − P(X)·δ. A point triangulated from true
// pixels then moves by δX = −N⁻¹ Σ_c J_X,cᵀ e_c(X), N = Σ_c J_X,cᵀ J_X,c (vision/triangulation's
// first solve, equal pick σ: an unmodelled bias has no covariance to weigh the views by). With each camera's
// shift of size d in an unknown direction, independent between cameras, the mean |δX|² over directions is Σ_c
// ½(|δX_c(d·ê_u)|² + |δX_c(d·ê_v)|²); the figure is its root mean over the flight-volume points. A camera
// whose principal point is free carries the shift in its estimate (its prior pulls it back by only
// (σ/σ_prior)² of δ) and is left out.
#include <Eigen/Core>
#include <vector>

#include "pipeline/io/correspondences_csv.hpp"
#include "vision/camera/calibration_result.hpp"

namespace rangecal {

/// One camera for the propagation: its calibration (camera and free parameters) and its lamp pairs
/// (those with `used` false are left out; sd_enu absent → `default_sd_m` per axis).
struct PrincipalPointCostCamera {
  const CalibrationResult* calibration = nullptr;
  const std::vector<Correspondence>* pairs = nullptr;
};

/// rms over `points` (m) of the calibration-only intersection bias when every camera whose principal
/// point is fixed has its true one `offset_px` away (direction-averaged, see above); 0 when no
/// camera holds it fixed; NaN when no point is seen by two cameras or a camera's F is singular.
/// Points seen by fewer than two cameras are skipped.
double principal_point_offset_bias_m(const std::vector<PrincipalPointCostCamera>& cams,
                                     const std::vector<Eigen::Vector3d>& points, double offset_px,
                                     double pixel_sigma_px, double default_sd_m = 0.01);

}  // namespace rangecal
