#pragma once
// What the network bundle is given besides its data (docs/optimisation.md "Network bundle"): each
// camera's starting values and per-camera options, the network-wide options, and the image-σ
// factor of its datum floor. The adjustment itself is optim/network/network_adjustment.hpp.
#include "gnss/track/ppk_error_model.hpp"
#include "optim/bundle/bundle_adjustment.hpp"
#include "optim/estimation/robust_loss.hpp"
#include "vision/camera/camera_model.hpp"

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
  /// With estimate_image_sigma: a camera whose residuals repeat themselves in time (their variance
  /// inflation F measured above 1, image_time_correlation.hpp) is weighed by its estimated
  /// σ·√F in a last solve, the PPK model estimated again with the image σ held and the outliers
  /// kept from the estimate's solve.
  bool image_time_correlation = true;
};

/// The network's datum floor (docs/accuracy_analysis.md, "Datum floor"): its joint covariance with
/// every centroid and pick σ divided by this factor. The images then fix the network's shape almost
/// exactly, and what remains is the datum — position, scale and orientation — as the PPK fixes and
/// control poles alone determine it (a similarity transform fitted to them). 100 is far enough: ten
/// times more moves the floor by < 0.3 % on the demo and five-ascent geometries (route_plan_test
/// holds it to 0.5 %).
inline constexpr double kDatumFloorImageFactor = 100;

}  // namespace rangecal
