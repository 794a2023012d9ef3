#pragma once
// What the single-camera bundle did (optim/bundle/bundle_adjustment.hpp): its solves, χ², variance factor,
// σ and outliers, for calibration.json's `details` (docs/outputs.md).
#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <vector>

#include "gnss/track/ppk_error_model.hpp"
#include "optim/estimation/robust_loss.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal {

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

}  // namespace rangecal
