#pragma once
// What the single-camera bundle is asked to solve (optim/bundle/bundle_adjustment.hpp, docs/optimisation.md
// `bundle`): the free parameters, the pixel σ, the priors, the robust loss and outlier test, and the PPK
// error model its covariance is stated under.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "gnss/track/ppk_error_model.hpp"
#include "optim/estimation/robust_loss.hpp"
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

}  // namespace rangecal
