#pragma once
// Single-camera bundle adjustment (docs/optimisation.md `bundle`): Ceres Levenberg–Marquardt over a chosen
// subset of the camera's parameters, from (world ENU point, pixel) pairs, with
//   - weights: each pixel residual whitened by its effective image covariance
//       C_i = σ_px²·I + J_X·Σ_X·J_Xᵀ    (optim/bundle/whitening.hpp)
//     so the world-point noise (1 cm at 64 m through 135 mm / 20 µm ≈ 1 px) is honestly counted;
//   - priors on the principal point and the camera centre as extra residual blocks;
//   - a robust loss (Huber or Cauchy, scale in whitened units) to find outliers, which are listed
//     and (by default) dropped before a final plain least-squares solve;
//   - covariance → 1σ and correlations of every free parameter, camera-centre covariance, the
//     a-posteriori variance factor (optim/bundle/bundle_covariance.hpp), and warnings for poorly
//     determined parameters (optim/bundle/bundle_diagnostics.hpp).
// Method, weighting and thresholds: docs/optimisation.md.
//
// Parameters: vision/camera/camera_parameters.hpp, f … clock_offset (the centre form of the pose).
// The clock offset δ = frame stamp − true exposure time: the lamp really stood at Xw − v·δ
// (optim/bundle/bundle_observation.hpp). The lamp moves up to 10 m/s, so 1 ms is up to 1 cm.
// Separable from the camera centre only where the velocity varies (ascents and descents,
// accelerations) or static points (control poles) are present; a constant velocity makes δ and the
// centre one direction, which the rank test reports.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "optim/bundle/bundle_details.hpp"
#include "optim/bundle/bundle_observation.hpp"
#include "optim/bundle/bundle_options.hpp"
#include "optim/bundle/calibration_warning.hpp"
#include "optim/bundle/whitening.hpp"
#include "vision/camera/calibration_result.hpp"
#include "vision/camera/camera_model.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal {

struct BundleResult {
  /// method "bundle"; parameters/covariance over the free parameters; rejected = outliers (when
  /// dropped); reprojection over the points used; warnings. Its `details` is left empty: the
  /// typed `details` below is what the bundle reports.
  CalibrationResult calibration;
  BundleDetails details;
  Eigen::MatrixXd covariance_unscaled;       ///< from the a-priori noise model
  Eigen::MatrixXd covariance_scaled;         ///< × variance_factor
  double chi2 = 0;                           ///< = details.chi2
  int dof = 0;                               ///< = details.dof
  double variance_factor = 0;                ///< = details.variance_factor
  bool rank_deficient = false;               ///< = details.rank_deficient
  std::vector<Eigen::Vector2d> residual_px;  ///< projected − observed, every input point
  std::vector<double> whitened_norm;         ///< ‖W·e‖ per point (σ units)
  std::vector<bool> outlier;                 ///< flagged by the threshold above
  int iterations = 0;                        ///< = details.iterations
  /// calibration.warnings typed (optim/bundle/calibration_warning.hpp): the same, in the same order.
  std::vector<CalibrationWarning> warnings;
};

/// Calibrates one camera. `initial` gives the starting values of the free parameters and the
/// fixed values of the others (and id, image size, pixel pitch). Throws rangecal::Error:
/// calibration kind for non-finite input (naming the observation and field), fewer residuals
/// than free parameters, all points on one line (pose free), points behind the initial camera,
/// or a failed solve; usage kind for an unknown free-parameter name. Rank-deficient covariance
/// is not an error: it is reported (rank_deficient, warnings, empty covariance).
BundleResult bundle_adjust(const Camera& initial, const std::vector<BundleObservation>& observations,
                           const BundleOptions& options = {});

/// The last step of a camera's result, the per-camera bundle's and each network camera's: the
/// warnings on poorly determined parameters and on the fit (optim/bundle/bundle_diagnostics.hpp)
/// appended to its typed warnings, each stamped with calibration.camera_id, calibration.warnings
/// their texts, and the details' summary copied to the result's own fields.
/// `max_speed_mps` is the camera's fastest lamp point (m/s).
void finish_bundle_result(double max_speed_mps, double correlation_warning, BundleResult* result);

}  // namespace rangecal
