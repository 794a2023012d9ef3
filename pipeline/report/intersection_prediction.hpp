#pragma once
// The intersection σ a range can expect for a target anywhere in the calibrated volume, from the
// calibrations and a pick σ (no picks, no survey): the first-order covariance of the triangulation
// of vision/triangulation/triangulation.hpp (triangulation_covariance_at) evaluated at a chosen
// world point X instead of a picked one, by every camera that sees X — the views weighted by their
// pick σ and their calibrations' covariance, the cross blocks of a joint (network) covariance when
// given: the same expressions the intersect stage evaluates at a pole (docs/intersection.md).
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
/// `cams` that see it, each pick with σ `pick_sigma_px` per axis (px, > 0). `cross` (indexed as
/// `cams`, blocks in each calibration's parameter order; null: independent cameras) holds the cross
/// blocks of a joint covariance. `weigh_calibration` as triangulation_covariance_at's (true: what
/// the intersect stage states).
PredictedIntersection predict_intersection(const std::vector<const CalibrationResult*>& cams,
                                           const Eigen::Vector3d& X_enu_m, double pick_sigma_px,
                                           const CrossCovariances* cross = nullptr,
                                           bool weigh_calibration = true);

/// √trace Σ_cal (m), the calibrations' part of the σ of a target picked with σ `pick_sigma_px`
/// (px, > 0), the views weighted by their picks alone (so that a calibration's slice and its datum
/// floor's are one estimate's, their ratio the covariances'), over an nx × ny grid of a horizontal
/// slice at height `up_m` (ENU U, m), cells covering [e_min, e_max] × [n_min, n_max] (m), values at cell
/// centres; NaN where fewer than two cameras see the point.
struct IntersectionSigmaSlice {
  double up_m = 0;
  std::vector<double> e_m;  ///< nx cell-centre eastings
  std::vector<double> n_m;  ///< ny cell-centre northings
  Eigen::MatrixXd sigma_m;  ///< ny × nx (row = north index)
};
IntersectionSigmaSlice intersection_sigma_slice(const std::vector<const CalibrationResult*>& cams,
                                                const Eigen::Vector2d& e_range_m,
                                                const Eigen::Vector2d& n_range_m, double up_m, int nx, int ny,
                                                double pick_sigma_px,
                                                const CrossCovariances* cross = nullptr);

}  // namespace rangecal
