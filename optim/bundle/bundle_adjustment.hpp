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
#include <optional>
#include <string>
#include <vector>

#include "gnss/track/ppk_error_model.hpp"
#include "optim/bundle/bundle_observation.hpp"
#include "optim/bundle/calibration_warning.hpp"
#include "optim/bundle/whitening.hpp"
#include "optim/estimation/robust_loss.hpp"
#include "vision/camera/calibration_result.hpp"
#include "vision/camera/camera_model.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal {

struct BundlePriors {
  bool use_principal_point = false;
  Eigen::Vector2d principal_point_px = Eigen::Vector2d::Zero();
  double principal_point_sigma_px = 0;
  bool use_center = false;
  Eigen::Vector3d center_enu_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d center_sigma_m = Eigen::Vector3d::Zero();  ///< per axis E, N, U
};

struct BundleOptions {
  /// Free parameters, as calibrate.free names them (expand_free_parameters,
  /// vision/camera/camera_parameters.hpp); the rest are held at the initial camera's values.
  std::vector<std::string> free = default_free_parameters();
  double pixel_sigma_px = 0.1;  ///< default σ of a pixel measurement (centroid noise)
  BundlePriors priors;
  RobustLoss loss = RobustLoss::huber;
  double loss_scale = 3.0;  ///< in whitened units (σ): Huber quadratic below, linear above
  /// Outlier if the final whitened residual ‖W·e‖ > outlier_threshold·max(1, s), s the robust
  /// scale (optim/estimation/robust_scale.hpp). 3.5 → 0.22 % false flags for Gaussian noise.
  double outlier_threshold = 3.5;
  bool resolve_without_outliers = true;  ///< final plain least squares on the inliers
  int max_iterations = 200;
  /// Starting value of the clock offset (s); also its fixed value when clock_offset is not free.
  double initial_clock_offset_s = 0;
  /// false (default): σ from the a-priori noise model (σ_px, Σ_X, ppk_error), honest when the noise is
  /// known; true: scaled by the a-posteriori variance factor χ²/dof. Both are always in `details`.
  /// Under a correlated ppk_error the factor checks the white part only (docs/optimisation.md "σ under
  /// correlated PPK errors"): scaling does not stand in for the model.
  bool scale_covariance = false;
  /// The PPK fixes' error model (gnss/track/ppk_error_model.hpp) under which the covariance is
  /// stated. The estimate is always weighed white (each fix under its own Σ_X); any model other than
  /// that weighting (white scale 1, no Gauss–Markov part: the default) makes the covariance the
  /// sandwich of optim/bundle/correlated_ppk_covariance.hpp, over the observations' time_s.
  PpkErrorModel ppk_error;
  double correlation_warning = 0.99;  ///< |ρ| above this → warning naming the pair
  /// Relative eigenvalue (of the column-scaled normal matrix) below which the covariance is
  /// declared rank-deficient.
  double rank_tolerance = 1e-14;
};

/// One Levenberg–Marquardt solve of the bundle.
struct BundleSolve {
  RobustLoss loss = RobustLoss::none;
  int iterations = 0;
  std::optional<std::size_t> rejected;  ///< the final solve: points dropped as outliers before it
};

/// What the bundle did, for calibration.json's `details` (written by pipeline/io).
struct BundleDetails {
  std::vector<CameraParameter> free;
  std::vector<BundleSolve> solves;
  int iterations = 0;              ///< Ceres iterations over all solves
  double chi2 = 0;                 ///< Σ whitened residual² + prior residual² (inliers)
  int dof = 0;                     ///< residuals − free parameters
  double variance_factor = 0;      ///< χ²/dof (≈ 1 when the noise model is right)
  bool covariance_scaled = false;  ///< BundleOptions::scale_covariance
  bool rank_deficient = false;
  double outlier_threshold_sigma = 0;  ///< the threshold applied (whitened units)
  double pixel_sigma_px = 0;           ///< the default pixel σ used
  /// F by which the network weighed the camera's centroids for residuals that repeat in time:
  /// pixel_sigma_px = the centroids' own σ × √F (optim/network/image_time_correlation.hpp); 1 else.
  double time_correlation_factor = 1;
  std::optional<double> clock_offset_s;  ///< when the clock offset was free
  /// 1σ of each free parameter from the a-priori noise model and scaled by √variance_factor;
  /// empty when the covariance is rank-deficient.
  Eigen::VectorXd sigma_unscaled, sigma_scaled;
  std::vector<std::size_t> outliers;  ///< indices of the observations flagged as outliers
  /// The PPK error model the σ are stated under, when it is not the bundle's own weighting
  /// (BundleOptions::ppk_error), and how many used observations its Gauss–Markov chain holds.
  std::optional<PpkErrorModel> ppk_error_model;
  int gauss_markov_states = 0;
};

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
