#pragma once
// Network bundle adjustment (docs/optimisation.md "Network bundle"): every camera and the lamp
// track adjusted together — self-calibrating bundle adjustment with weighted control, as
// photogrammetric networks are adjusted (Triggs et al. 2000 §6 on the Schur complement; Granshaw
// 1980 on self-calibration). Parameters:
//   - each camera's free set (BundleOptions::free, clock offset included), its priors as in the
//     per-camera bundle (optim/bundle/bundle_adjustment.hpp);
//   - one 3-vector per point: each used lamp epoch under its PPK prior (full 3×3 covariance), each
//     control pole under its survey prior.
// Cost: Σ ρ(‖r_img‖²) over image residuals (in σ_px units) + Σ ‖L⁻¹(X_k − X̄_k)‖² over the priors in
// use + the camera priors. The gauge (datum: position, scale, orientation) is fixed by the priors
// alone. Ceres Levenberg–Marquardt with the point blocks eliminated first (DENSE_SCHUR: the
// reduced camera system is at most a few hundred parameters).
//
// Steps (network_adjustment.cpp): robust solve (Huber or Cauchy on image residuals and on the
// priors), PPK outliers (optim/network/network_outliers.hpp: epochs whose multi-ray position
// disagrees with their fix, whitened test; prior dropped), image outliers (the per-camera bundle's
// rule), with NetworkOptions::estimate_ppk_error the variance components (PPK model, each camera's
// image σ: optim/network/ppk_error_estimation.hpp), a plain least-squares solve without the
// outliers, then the joint covariance of all cameras (the Schur complement,
// optim/network/network_covariance.hpp) and each adjusted point's covariance. When a camera's
// estimated centroid σ is more than 1.5× off its stated σ, the steps run once more at the estimated
// σ, so that the outlier tests weigh each ray by what it is worth.
//
// A camera that shares no epoch with another is calibrated from its own epochs exactly as the
// per-camera bundle would: eliminating a point seen once under its prior gives the bundle's
// effective pixel covariance σ_px²·I + J_X·Σ_X·J_Xᵀ (Woodbury identity).
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "gnss/track/ppk_error_model.hpp"
#include "optim/bundle/bundle_adjustment.hpp"
#include "optim/network/network_observation.hpp"

namespace rangecal {

/// One camera of the network: its starting values (and fixed values of what is not free) and its
/// per-camera options — free set, pixel σ, priors, initial clock offset, correlation warning. The
/// robust loss, outlier thresholds, iterations, covariance scaling and rank tolerance are the
/// network's (NetworkOptions); those fields of `options` are not read.
struct NetworkCamera {
  Camera initial;
  BundleOptions options;
};

struct NetworkOptions {
  RobustLoss loss = RobustLoss::huber;
  double loss_scale = 3.0;  ///< in σ units, on image residuals and on the priors' whitened norm
  /// Image outlier rule of the per-camera bundle (BundleOptions::outlier_threshold), per camera.
  double outlier_threshold = 3.5;
  /// PPK outlier rule (network_outliers.hpp): an epoch seen by ≥ 2 cameras whose adjusted position
  /// disagrees with its fix by a whitened d² above the χ²_m quantile of this tail probability
  /// (m the test's redundancy, ≤ 3). 1e-4 → 2 false flags in 20,000 clean epochs.
  double ppk_outlier_probability = 1e-4;
  bool resolve_without_outliers = true;  ///< final plain least squares without the outliers
  /// > 0: also the datum floor (NetworkResult::datum_floor_covariance) with every image σ divided by
  /// this factor (kDatumFloorImageFactor); 0: not computed (it costs one more joint covariance).
  double datum_floor_image_factor = 0;
  int max_iterations = 200;
  int num_threads = 1;  ///< Ceres threads (1: deterministic)
  /// The joint covariance and every camera's: false, from the a-priori noise model; true, scaled by
  /// the network's variance factor χ²/dof (BundleOptions::scale_covariance for the network).
  bool scale_covariance = false;
  /// The joint covariance's rank test (BundleOptions::rank_tolerance for the network).
  double rank_tolerance = 1e-14;
  /// The PPK fixes' error model (gnss/track/ppk_error_model.hpp): the default is white, each fix under its
  /// own .pos covariance; with a Gauss–Markov part the epochs with a time (NetworkPoint::time_s) are chained.
  PpkErrorModel ppk_error;
  /// Estimate the model from the mission (ppk_error_estimation.hpp) instead: `ppk_error` then only
  /// weighs the robust solve and the outlier tests (white by default), the final solve and every σ
  /// use the estimate.
  bool estimate_ppk_error = false;
  /// With estimate_ppk_error: each camera's lamp-centroid σ estimated with the model (its image
  /// variance component, restricted_likelihood.hpp), and the final solve and every σ use it; false
  /// holds the stated σ (BundleOptions::pixel_sigma_px).
  bool estimate_image_sigma = true;
  /// With estimate_ppk_error: the white family alone (the white scales and image scales), when a
  /// check outside the network has refused the correlated model (docs/optimisation.md "The guarded
  /// model").
  bool estimate_white_only = false;
};

/// The network's datum floor (docs/accuracy_analysis.md, "Datum floor"): its joint covariance with
/// every centroid and pick σ divided by this factor. The images then fix the network's shape almost
/// exactly, and what remains is the datum — position, scale and orientation — as the PPK fixes and
/// control poles alone determine it (a similarity transform fitted to them). 100 is far enough: ten
/// times more moves the floor by < 0.3 % on the demo and five-ascent geometries (route_plan_test
/// holds it to 0.5 %).
inline constexpr double kDatumFloorImageFactor = 100;

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

/// Adjusts the network. Throws rangecal::Error: calibration kind for non-finite input (naming
/// the observation or point), an observation of an unknown camera or point, a prior covariance
/// that is not positive definite, a camera with fewer residuals than free parameters, a point
/// behind a starting camera, or a failed solve; usage kind for an unknown free-parameter name.
NetworkResult network_adjust(const std::vector<NetworkCamera>& cameras,
                             const std::vector<NetworkPoint>& points,
                             const std::vector<NetworkObservation>& observations,
                             const NetworkOptions& options = {});

}  // namespace rangecal
