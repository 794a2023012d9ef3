#pragma once
// The intersection σ a range can expect for a target anywhere in the calibrated volume, from the
// calibrations alone (no picks, no survey): the first-order covariance of the triangulation of
// vision/triangulation/triangulation.hpp evaluated at a chosen world point X instead of a picked one.
// With J_i = ∂pixel_i/∂X and K_i = ∂pixel_i/∂θ_i at X for every camera that sees X, and equal pick
// σ in every camera (so the weights cancel from the calibration term),
//   N = Σ J_iᵀ J_i,   Σ_cal = Σ_i Σ_j N⁻¹ J_iᵀ K_i Σθ_ij K_jᵀ J_j N⁻¹,   Σ_pick = σ_pick² N⁻¹,
// with Σθ_ij = 0 for i ≠ j unless a joint (network) covariance gives the cross blocks: the same
// expressions the intersect stage evaluates at a pole (docs/intersection.md).
#include <Eigen/Core>
#include <vector>

#include "vision/camera/calibration_result.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

struct PredictedIntersection {
  int n_cameras = 0;  ///< cameras that see X (in front, on the image); < 2: no intersection
  Eigen::Matrix3d cov_calibration_m2 = Eigen::Matrix3d::Zero();  ///< from the calibrations (m²)
  Eigen::Matrix3d cov_pick_m2 = Eigen::Matrix3d::Zero();         ///< from the pick noise (m²)
};

/// The predicted covariance of the intersection of world point `X_enu_m` (m) by the cameras of
/// `cams` that see it, each pick with σ `pick_sigma_px` per axis (px; 0 for calibration only).
/// `cross` (indexed as `cams`, blocks in each calibration's parameter order; null: independent
/// cameras) holds the cross blocks of a joint covariance.
PredictedIntersection predict_intersection(const std::vector<const CalibrationResult*>& cams,
                                           const Eigen::Vector3d& X_enu_m, double pick_sigma_px,
                                           const CrossCovariances* cross = nullptr);

/// √trace Σ_cal (m) over an nx × ny grid of a horizontal slice at height `up_m` (ENU U, m), cells
/// covering [e_min, e_max] × [n_min, n_max] (m), values at cell centres; NaN where fewer than two
/// cameras see the point.
struct IntersectionSigmaSlice {
  double up_m = 0;
  std::vector<double> e_m;  ///< nx cell-centre eastings
  std::vector<double> n_m;  ///< ny cell-centre northings
  Eigen::MatrixXd sigma_m;  ///< ny × nx (row = north index)
};
IntersectionSigmaSlice intersection_sigma_slice(const std::vector<const CalibrationResult*>& cams,
                                                const Eigen::Vector2d& e_range_m,
                                                const Eigen::Vector2d& n_range_m, double up_m, int nx, int ny,
                                                const CrossCovariances* cross = nullptr);

}  // namespace rangecal
