#pragma once
// Single-camera bundle adjustment (SPEC §4.4 `bundle`): Ceres Levenberg–Marquardt over a chosen
// subset of the camera's parameters, from (world ENU point, pixel) pairs, with
//   - weights: each pixel residual whitened by its effective image covariance
//       C_i = σ_px²·I + J_X·Σ_X·J_Xᵀ    (J_X = ∂pixel/∂world point, Σ_X the point's PPK covariance)
//     so the world-point noise (1 cm at 64 m through 135 mm / 20 µm ≈ 1 px) is honestly counted;
//   - priors on the principal point and the camera centre as extra residual blocks;
//   - a robust loss (Huber or Cauchy, scale in whitened units) to find outliers, which are listed
//     and (by default) dropped before a final plain least-squares solve;
//   - covariance → 1σ and correlations of every free parameter, camera-centre covariance, the
//     a-posteriori variance factor, and warnings for poorly determined parameters.
// Method, weighting and thresholds: docs/optimisation.md.
//
// Parameters (CalibrationResult naming, vision/camera/calibration_result.hpp):
//   f (mm), sx, u0, v0 (px), k1 k2 k3 p1 p2 a1 a2 (distorted → undistorted, sensor mm),
//   wx wy wz (rad): rotation perturbation R = exp([w]×)·R̂ about the final R̂ (camera axes),
//   CE CN CU (m): camera centre in ENU (Xc = R·(Xw − C), T = −R·C),
//   clock_offset (s): camera clock − GNSS time, δ = frame stamp − true exposure time. The world
//     point was interpolated at the frame's stamp, so the lamp really stood at
//       X(t_true) = X(stamp − δ) ≈ Xw − v·δ        (v the lamp velocity at the stamp)
//     and that is what the camera saw (docs/optimisation.md "Clock offset"). The lamp moves up to
//     10 m/s, so 1 ms is up to 1 cm. Separable from the camera centre only where the velocity
//     varies (ascents and descents, accelerations) or static points (control poles) are present;
//     a constant velocity makes δ and the centre one direction, which the rank test reports.
// Free-parameter names accepted in BundleOptions::free: f, sx, u0, v0, k1, k2, k3, p1, p2, a1, a2,
// pose (= rotation + center), rotation (wx wy wz), center (CE CN CU), clock_offset.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "vision/camera/calibration_result.hpp"
#include "vision/camera/camera_model.hpp"

namespace rangecal {

struct BundleObservation {
  Eigen::Vector3d world = Eigen::Vector3d::Zero();      ///< ENU, m
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();      ///< (u, v), px
  Eigen::Matrix3d world_cov = Eigen::Matrix3d::Zero();  ///< Σ_X, m² (e.g. diag(sdE², sdN², sdU²))
  double pixel_sigma_px = 0;  ///< σ_px of this pixel; ≤ 0 → BundleOptions::pixel_sigma_px
  /// Lamp velocity (ENU, m/s) at the observation's time stamp (Hermite derivative of the track);
  /// zero for static points such as poles. Used only when clock_offset is free (or nonzero).
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
};

/// The world point the camera saw: Xw − v·δ for a camera clock offset δ (s), see above.
inline Eigen::Vector3d observed_world_point(const BundleObservation& o, double clock_offset_s) {
  return o.world - o.velocity * clock_offset_s;
}

struct BundlePriors {
  bool use_principal_point = false;
  Eigen::Vector2d principal_point_px = Eigen::Vector2d::Zero();
  double principal_point_sigma_px = 0;
  bool use_center = false;
  Eigen::Vector3d center_enu_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d center_sigma_m = Eigen::Vector3d::Zero();  ///< per axis E, N, U
};

enum class RobustLoss { none, huber, cauchy };

struct BundleOptions {
  /// Free parameters (names above); the rest are held at the initial camera's values.
  std::vector<std::string> free = {"f", "k1", "pose"};
  double pixel_sigma_px = 0.1;  ///< default σ of a pixel measurement (centroid noise)
  BundlePriors priors;
  RobustLoss loss = RobustLoss::huber;
  double loss_scale = 3.0;  ///< in whitened units (σ): Huber quadratic below, linear above
  /// Outlier if the final whitened residual ‖W·e‖ > outlier_threshold·max(1, s), s the robust
  /// scale median‖W·e‖/√(2 ln 2) (the median of a χ₂ variable), so an over-optimistic σ_px does
  /// not flag everything. 3.5 → 0.22 % false flags for Gaussian noise.
  double outlier_threshold = 3.5;
  bool resolve_without_outliers = true;  ///< final plain least squares on the inliers
  int max_iterations = 200;
  /// Starting value of the clock offset (s); also its fixed value when clock_offset is not free.
  double initial_clock_offset_s = 0;
  /// false (default): σ from the a-priori noise model (σ_px, Σ_X), honest when the noise is known;
  /// true: scaled by the a-posteriori variance factor χ²/dof. Both are always in `details`.
  bool scale_covariance = false;
  double correlation_warning = 0.99;  ///< |ρ| above this → warning naming the pair
  /// Relative eigenvalue (of the column-scaled normal matrix) below which the covariance is
  /// declared rank-deficient.
  double rank_tolerance = 1e-14;
};

struct BundleResult {
  /// method "bundle"; parameter_names/covariance over the free parameters; rejected = outliers
  /// (when dropped); reprojection over the points used; warnings; details (iterations, χ², dof,
  /// variance factor, scaled σ, outliers, stages).
  CalibrationResult calibration;
  Eigen::MatrixXd covariance_unscaled;  ///< from the a-priori noise model
  Eigen::MatrixXd covariance_scaled;    ///< × variance_factor
  double chi2 = 0;                      ///< Σ whitened residual² + prior residual² (inliers)
  int dof = 0;                          ///< residuals − free parameters
  double variance_factor = 0;           ///< χ²/dof (≈ 1 when the noise model is right)
  bool rank_deficient = false;
  std::vector<Eigen::Vector2d> residual_px;  ///< projected − observed, every input point
  std::vector<double> whitened_norm;         ///< ‖W·e‖ per point (σ units)
  std::vector<bool> outlier;                 ///< flagged by the threshold above
  int iterations = 0;                        ///< Ceres iterations over all stages
};

/// Calibrates one camera. `initial` gives the starting values of the free parameters and the
/// fixed values of the others (and id, image size, pixel pitch). Throws rangecal::Error:
/// calibration kind for non-finite input (naming the observation and field), fewer residuals
/// than free parameters, all points on one line (pose free), points behind the initial camera,
/// or a failed solve; usage kind for an unknown free-parameter name. Rank-deficient covariance
/// is not an error: it is reported (rank_deficient, warnings, empty covariance).
BundleResult bundle_adjust(const Camera& initial, const std::vector<BundleObservation>& observations,
                           const BundleOptions& options = {});

/// ∂(u, v)/∂Xw (2×3, px/m) of `cam` at world point Xw (autodiff through the camera model).
Eigen::Matrix<double, 2, 3> pixel_jacobian_wrt_world(const Camera& cam, const Eigen::Vector3d& Xw);

}  // namespace rangecal
