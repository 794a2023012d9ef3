#pragma once
// What the network bundle gives back (docs/optimisation.md "Network bundle"): each camera's
// calibration, the joint covariance, each adjusted point, the statistics, what the float epochs
// add and the datum floor. The adjustment itself is optim/network/network_adjustment.hpp.
#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "gnss/track/ppk_error_model.hpp"
#include "optim/bundle/bundle_adjustment.hpp"

namespace rangecal {

/// One adjusted point (a row of gnss/lamp_track_adjusted.csv for a lamp epoch).
struct NetworkPointResult {
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();         ///< adjusted, ENU m
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();         ///< its a-priori covariance (m²), cameras included
  Eigen::Vector3d correction = Eigen::Vector3d::Zero();  ///< adjusted − prior (m)
  int cameras = 0;           ///< cameras whose (inlier) image observations the final solve used
  bool used = false;         ///< in the final solve (some observation or a prior)
  bool prior_used = false;   ///< its prior entered the final solve
  bool ppk_outlier = false;  ///< flagged by the PPK outlier test (prior dropped)
  double ppk_test_d2 = 0;    ///< whitened d² of the test (0 when not tested)
  int ppk_test_dof = 0;      ///< its redundancy m (0 when not tested)
  /// The estimated Gauss–Markov part of its fix's error, g (ENU m; gnss/track/ppk_error_model.hpp): zero for
  /// a point outside the chain.
  Eigen::Vector3d ppk_gm = Eigen::Vector3d::Zero();
};

struct NetworkStatistics {
  double chi2 = 0;             ///< Σ r² of the final solve (image, point priors, camera priors)
  int dof = 0;                 ///< residuals − parameters
  double variance_factor = 0;  ///< χ²/dof
  int epochs_seen_by_1 = 0, epochs_seen_by_2 = 0, epochs_seen_by_3_or_more = 0;  ///< lamp epochs
  int float_epochs_used = 0;              ///< lamp epochs of quality ≥ 2 in the final solve
  std::vector<std::size_t> ppk_outliers;  ///< point indices
  int image_outliers = 0;
  int iterations = 0;  ///< Ceres iterations over all solves
  bool rank_deficient = false;
  /// Cameras (indices) that share no used epoch with any other camera: calibrated from their own
  /// epochs alone, as the per-camera bundle would.
  std::vector<std::size_t> cameras_alone;
  /// Under a correlated model: the independent looks at the PPK error that the fixes in the final
  /// solve give, horizontal and vertical (gauss_markov_looks); 0 when white.
  double ppk_looks_h = 0, ppk_looks_v = 0;
};

/// What the float epochs add (gnss.accept_quality with 2; docs/optimisation.md, "Float epochs"):
/// each camera's a-priori σ of its free parameters with the float epochs and without them — the
/// joint covariance at the same solution with their priors and image observations left out.
struct FloatEpochContribution {
  int epochs = 0;  ///< float epochs in the final solve; 0: none, and the vectors are empty
  std::vector<Eigen::VectorXd> sigma_with;     ///< per camera, its calibration.parameters order
  std::vector<Eigen::VectorXd> sigma_without;  ///< per camera; empty when undetermined without them
};

struct NetworkResult {
  /// Per camera, in input order: calibration (method "network", covariance = its marginal of the
  /// joint covariance), details, residuals and outlier flags over that camera's observations in
  /// input order (camera_observations).
  std::vector<BundleResult> cameras;
  std::vector<std::vector<std::size_t>> camera_observations;  ///< network observation indices
  /// Joint covariance of every camera's free parameters (cameras in order, each in its
  /// calibration.parameters order, from joint_offset[c]); a-priori or scaled as
  /// NetworkOptions::scale_covariance; empty when rank-deficient.
  Eigen::MatrixXd joint_covariance;
  std::vector<int> joint_offset;
  std::vector<NetworkPointResult> points;
  NetworkStatistics statistics;
  FloatEpochContribution float_epochs;
  /// The datum floor (kDatumFloorImageFactor): joint_covariance's layout and scaling, at the same
  /// solution and selection, every image σ divided by datum_floor_image_factor. Empty when not asked
  /// for (NetworkOptions::datum_floor_image_factor = 0) or rank-deficient.
  Eigen::MatrixXd datum_floor_covariance;
  double datum_floor_image_factor = 0;
  std::vector<std::string> warnings;  ///< network-wide (camera warnings are in each calibration)
  PpkErrorModel ppk_error;            ///< the model the fixes were weighed by (NetworkOptions::ppk_error)
  /// The estimate, when NetworkOptions::estimate_ppk_error (ppk_error is then its model).
  std::optional<PpkErrorEstimate> ppk_estimate;
  int gauss_markov_states = 0;  ///< epochs in its chain (0: white)
};

}  // namespace rangecal
