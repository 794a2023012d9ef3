#pragma once
// The two calibration methods compared before flying (docs/accuracy_analysis.md `plan`, "Network
// beside per-camera"; docs/optimisation.md "Network bundle"): on the noise-free network a scenario
// gives (network_plan.hpp), the joint covariance of the per-camera calibrations — cross blocks
// included — and the calibration-only intersection σ either method predicts through the flight
// volume.
//
// Per-camera cross-covariance. Camera c alone minimises Σ_i e_iᵀ C_i⁻¹ e_i, e_i = π_c(θ_c, X̄_i) − u_i,
// with X̄_i the PPK fix (or surveyed pole) and C_i = σ_px²·I + J_X,i·Σ_i·J_X,iᵀ. To first order
// (F_c = Σ_i J_iᵀ C_i⁻¹ J_i):
//     θ̂_c − θ_c ≈ −F_c⁻¹ Σ_i J_iᵀ C_i⁻¹ (J_X,i·ε_k(i) − n_i),
// n_i the camera's pixel noise, ε_k the error of fix k. Pixel noise is the camera's own, but every
// camera that sees epoch k (or pole k) reads the same ε_k, so for cameras a ≠ b
//     Cov(θ̂_a, θ̂_b) = F_a⁻¹ [Σ_k A_ak·Σ_k·A_bkᵀ] F_b⁻¹,     A_ck = J_ckᵀ C_ck⁻¹ J_X,ck,
// summed over the points k both see; for a = b the same expression gives F_a⁻¹ back. Cameras
// calibrated separately from one track are therefore correlated: they share the track's datum error.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/analysis/network_plan.hpp"

namespace rangecal {

/// Lamp epochs (not poles) of `n` seen by ≥ 2 cameras: with any, `rangecal run` calibrates the
/// cameras as a network (the default method); without, each camera alone.
int shared_epochs(const PlannedNetwork& n);

/// The per-camera calibrations' joint covariance (cameras in order, each camera's parameters
/// expand_free_parameters(free)): diagonal blocks F_c⁻¹ (cramer_rao_bound on the camera's
/// observations as the bundle sees them), off-diagonal blocks the shared-fix cross-covariance above.
/// Empty when a camera's F is singular.
Eigen::MatrixXd per_camera_joint_covariance(const PlannedNetwork& n, const std::vector<std::string>& free,
                                            const PlanOptions& options = {});

/// Up to `count` points uniform in the box of the network's lamp epochs (fixed `seed`), each inside
/// the image of ≥ 2 truth cameras: the flight volume the intersection σ is predicted over. Fewer
/// when after 100·count draws not enough are seen (cameras that hardly overlap).
std::vector<Eigen::Vector3d> flight_volume_points(const PlannedNetwork& n, int count, std::uint64_t seed);

/// √(mean over `points` of trace Σ_cal) (m): the rms calibration-only 3-D error of a point
/// triangulated from noise-free pixels by the cameras that see it, for calibration covariance
/// `joint` (blocks as per_camera_joint_covariance; vision/triangulation/triangulation.hpp Σ_cal),
/// with its cross-camera blocks when `with_cross`, else the cameras taken as independent. Points
/// that cannot be triangulated (parallel rays) are skipped; NaN when `joint` is empty or none is left.
double predicted_intersection_rms(const std::vector<Camera>& truth,
                                  const std::vector<CameraParameter>& params, const Eigen::MatrixXd& joint,
                                  const std::vector<Eigen::Vector3d>& points, bool with_cross);

}  // namespace rangecal
