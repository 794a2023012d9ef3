#include "optim/network/network_adjustment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "optim/estimation/center_covariance.hpp"
#include "optim/estimation/reprojection_stats.hpp"
#include "optim/network/image_time_correlation.hpp"
#include "optim/network/network_ceres_problem.hpp"
#include "optim/network/network_covariance.hpp"
#include "optim/network/network_gauss_newton.hpp"
#include "optim/network/network_input_checks.hpp"
#include "optim/network/network_outliers.hpp"
#include "optim/network/network_parameters.hpp"
#include "optim/network/ppk_error_estimation.hpp"

namespace rangecal {
namespace {

// ---------------------------------------------------------------------------------------------
// Set-up.

/// Number of cameras with a used observation of each point.
std::vector<int> cameras_per_point(const NetworkLayout& layout, const NetworkSelection& selection) {
  std::vector<int> count(layout.by_point.size(), 0);
  for (std::size_t k = 0; k < layout.by_point.size(); ++k) {
    std::vector<std::size_t> seen;
    for (std::size_t i : layout.by_point[k])
      if (selection.observation[i]) seen.push_back((*layout.observations)[i].camera);
    std::sort(seen.begin(), seen.end());
    count[k] = static_cast<int>(std::unique(seen.begin(), seen.end()) - seen.begin());
  }
  return count;
}

/// A point without a prior needs two cameras' rays; a point without observations leaves the solve.
void drop_undetermined_points(const NetworkLayout& layout, NetworkSelection* selection) {
  const std::vector<int> seen = cameras_per_point(layout, *selection);
  for (std::size_t k = 0; k < seen.size(); ++k) {
    if (seen[k] == 0) selection->prior[k] = 0;
    if (!selection->prior[k] && seen[k] < 2)
      for (std::size_t i : layout.by_point[k]) selection->observation[i] = 0;
  }
}

// ---------------------------------------------------------------------------------------------
// Solving (network_ceres_problem.hpp).

/// Relative tolerances (Ceres' function and parameter tolerance) of a solve whose result is the
/// network's, and of the robust solve that only separates outliers before the final least-squares
/// solve starts from it: under a robust loss the iterations converge linearly, and what remains
/// after a relative step of 1e-6 is far below the outlier test's resolution (measured in
/// docs/performance.md, "Network bundle — solver settings").
constexpr double kFinalTolerance = 1e-12;
constexpr double kSeparatingTolerance = 1e-6;

/// Takes the image outliers of `test` out of the selection, and the points they leave
/// undetermined. Throws rangecal::Error (calibration) when a camera is left with fewer residuals
/// than free parameters.
void drop_image_outliers(const NetworkLayout& layout, const ImageOutlierTest& test,
                         NetworkSelection* selection) {
  const std::vector<NetworkObservation>& observations = *layout.observations;
  for (std::size_t i = 0; i < observations.size(); ++i)
    if (test.outlier[i]) selection->observation[i] = 0;
  drop_undetermined_points(layout, selection);
  for (std::size_t c = 0; c < layout.setups.size(); ++c) {
    int used = 0;
    for (std::size_t i = 0; i < observations.size(); ++i)
      used += observations[i].camera == c && selection->observation[i] ? 1 : 0;
    if (2 * used < layout.setups[c].n_free)
      throw_calibration_error("network", (*layout.cameras)[c].initial.id +
                                             ": after rejecting outliers too few points remain (" +
                                             std::to_string(used) + ")");
  }
}

// ---------------------------------------------------------------------------------------------
// Results.

double scene_distance(const NetworkLayout& layout) {
  double sum = 0;
  int count = 0;
  for (const NetworkObservation& observation : *layout.observations) {
    sum += (layout.starts[observation.camera].pose.center() - (*layout.points)[observation.point].prior_enu)
               .norm();
    ++count;
  }
  return std::max(1.0, count > 0 ? sum / count : 1.0);
}

/// The fastest lamp speed (m/s) over the observations of `camera`, or of every camera when none is
/// named: it ranges the clock offset in the rank test and its warning.
double max_speed(const NetworkLayout& layout, std::optional<std::size_t> camera = std::nullopt) {
  double speed = 0;
  for (const NetworkObservation& observation : *layout.observations)
    if (!camera || observation.camera == *camera) speed = std::max(speed, observation.velocity.norm());
  return speed;
}

void count_epochs(const NetworkLayout& layout, const NetworkSelection& selection, NetworkStatistics* stats) {
  const std::vector<int> seen = cameras_per_point(layout, selection);
  for (std::size_t k = 0; k < seen.size(); ++k) {
    const NetworkPoint& point = (*layout.points)[k];
    if (point.control_pole || seen[k] == 0) continue;
    if (seen[k] == 1)
      ++stats->epochs_seen_by_1;
    else if (seen[k] == 2)
      ++stats->epochs_seen_by_2;
    else
      ++stats->epochs_seen_by_3_or_more;
    if (point.quality >= 2) ++stats->float_epochs_used;
  }
  // Cameras sharing no used epoch (or pole) with another camera.
  std::vector<char> shares(layout.starts.size(), 0);
  for (std::size_t k = 0; k < seen.size(); ++k) {
    if (seen[k] < 2) continue;
    for (std::size_t i : layout.by_point[k])
      if (selection.observation[i]) shares[(*layout.observations)[i].camera] = 1;
  }
  for (std::size_t c = 0; c < shares.size(); ++c)
    if (!shares[c]) stats->cameras_alone.push_back(c);
}

/// The final solve's χ², degrees of freedom and variance factor, and the epochs' counts.
void fill_statistics(const NetworkLayout& layout, const NetworkSelection& selection,
                     const NetworkCovariance& cov, NetworkStatistics* stats) {
  stats->chi2 = cov.chi2;
  stats->dof = cov.residuals - cov.parameters;
  stats->variance_factor =
      stats->dof > 0 ? stats->chi2 / stats->dof : std::numeric_limits<double>::quiet_NaN();
  stats->rank_deficient = cov.rank_deficient;
  count_epochs(layout, selection, stats);
}

/// Each point's adjusted position, covariance and use in the final solve.
void fill_point_results(const NetworkLayout& layout, const NetworkSelection& selection,
                        const NetworkCovariance& cov, std::vector<NetworkPointResult>* points) {
  const std::vector<int> seen = cameras_per_point(layout, selection);
  for (std::size_t k = 0; k < points->size(); ++k) {
    NetworkPointResult& result = (*points)[k];
    result.enu = cov.point_enu[k];
    result.correction = result.enu - (*layout.points)[k].prior_enu;
    result.cov = cov.point_cov[k];
    result.ppk_gm = cov.point_gm[k];
    result.cameras = seen[k];
    result.prior_used = selection.prior[k] != 0;
    result.used = result.prior_used || seen[k] > 0;
  }
}

/// σ of each camera's free parameters (free order) from `cov`'s joint covariance (a-priori); an
/// empty vector for every camera when it is rank-deficient.
std::vector<Eigen::VectorXd> camera_sigmas(const NetworkLayout& layout, const NetworkCovariance& cov) {
  std::vector<Eigen::VectorXd> sigmas(layout.setups.size());
  if (cov.rank_deficient || cov.joint.size() == 0) return sigmas;
  for (std::size_t c = 0; c < sigmas.size(); ++c)
    sigmas[c] = cov.joint.diagonal().segment(layout.offset[c], layout.setups[c].n_free).cwiseSqrt();
  return sigmas;
}

/// The float epochs' share: the covariance again at the same solution with their priors and image
/// observations left out (a linearised "without them", no second solve).
FloatEpochContribution float_epoch_contribution(const NetworkLayout& layout,
                                                const NetworkParameterBlocks& blocks,
                                                const NetworkSelection& selection,
                                                const NetworkCovariance& with, int epochs,
                                                double rank_tolerance) {
  FloatEpochContribution contribution;
  contribution.epochs = epochs;
  contribution.sigma_with = camera_sigmas(layout, with);
  NetworkSelection without = selection;
  for (std::size_t k = 0; k < layout.by_point.size(); ++k) {
    const NetworkPoint& point = (*layout.points)[k];
    if (point.control_pole || point.quality < 2) continue;
    without.prior[k] = 0;
    for (std::size_t i : layout.by_point[k]) without.observation[i] = 0;
  }
  drop_undetermined_points(layout, &without);
  refresh_single_view(layout, blocks, &without);
  contribution.sigma_without = camera_sigmas(
      layout,
      network_covariance(layout, blocks, without, scene_distance(layout), max_speed(layout), rank_tolerance));
  return contribution;
}

/// The datum floor: the joint covariance again at the same solution and selection with every image
/// σ divided by `factor` (single-view weights recomputed with it), scaled as the network's.
Eigen::MatrixXd datum_floor_covariance(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                                       NetworkSelection selection, double factor, double scale,
                                       double rank_tolerance) {
  NetworkLayout sharp = layout;
  sharp.pixel_sigma_scale = 1 / factor;
  refresh_single_view(sharp, blocks, &selection);
  const NetworkCovariance cov =
      network_covariance(sharp, blocks, selection, scene_distance(layout), max_speed(layout), rank_tolerance);
  if (cov.rank_deficient || cov.joint.size() == 0) return {};
  return cov.joint * scale;
}

/// The datum floor into `out` when asked for, or the warning that it is rank-deficient.
void add_datum_floor(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                     const NetworkSelection& selection, const NetworkOptions& options, double scale,
                     NetworkResult* out) {
  if (!(options.datum_floor_image_factor > 0 && out->joint_covariance.size() > 0)) return;
  out->datum_floor_covariance = datum_floor_covariance(
      layout, blocks, selection, options.datum_floor_image_factor, scale, options.rank_tolerance);
  if (out->datum_floor_covariance.size() > 0)
    out->datum_floor_image_factor = options.datum_floor_image_factor;
  else
    out->warnings.push_back("the datum floor (images " +
                            format_number("%g", options.datum_floor_image_factor) +
                            "x sharper) is rank-deficient at the rank tolerance: not computed");
}

/// A camera's covariance: its marginal of the joint covariance, a-priori and scaled by the
/// network's variance factor; the rank-deficiency warnings when there is none.
void camera_covariance(const NetworkLayout& layout, std::size_t camera, const NetworkCovariance& cov,
                       const NetworkStatistics& stats, bool scale_covariance, BundleResult* out) {
  BundleDetails& details = out->details;
  CalibrationResult& cal = out->calibration;
  if (cov.rank_deficient || cov.joint.size() == 0) {
    out->warnings = rank_deficiency_warnings(cov.warnings, cov.named, layout.free[camera], cal.camera_id,
                                             static_cast<Eigen::Index>(layout.offset[camera]));
    return;
  }
  const int n_free = layout.setups[camera].n_free;
  const int first = layout.offset[camera];
  out->covariance_unscaled = cov.joint.block(first, first, n_free, n_free);
  out->covariance_scaled =
      out->covariance_unscaled * (std::isfinite(stats.variance_factor) ? stats.variance_factor : 1.0);
  cal.covariance = scale_covariance ? out->covariance_scaled : out->covariance_unscaled;
  details.sigma_unscaled = out->covariance_unscaled.diagonal().cwiseSqrt();
  details.sigma_scaled = out->covariance_scaled.diagonal().cwiseSqrt();
  cal.center_covariance_m2 = center_covariance(cal);
}

/// A camera's residuals, whitened norms and outlier flags over its observations `mine`, and its
/// reprojection statistics over those in the final solve.
void camera_residuals(const std::vector<std::size_t>& mine, const ImageOutlierTest& test,
                      const std::vector<bool>& dropped, const NetworkSelection& selection,
                      BundleResult* out) {
  std::vector<char> used;
  for (std::size_t j = 0; j < mine.size(); ++j) {
    const std::size_t i = mine[j];
    out->residual_px.push_back(test.residual_px[i]);
    out->whitened_norm.push_back(test.whitened_norm[i]);
    out->outlier.push_back(dropped[i]);
    used.push_back(selection.observation[i]);
    if (dropped[i]) {
      out->calibration.rejected.push_back(j);
      out->details.outliers.push_back(j);
    }
  }
  out->calibration.reprojection = reprojection_stats(out->residual_px, used);
}

/// Camera `index`'s result: its marginal of the joint covariance, residuals and flags of its
/// observations `mine`.
BundleResult camera_result(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                           std::size_t index, const std::vector<std::size_t>& mine,
                           const ImageOutlierTest& test, const std::vector<bool>& dropped,
                           const NetworkSelection& selection, const NetworkCovariance& cov,
                           const NetworkStatistics& stats, int n_solves, bool scale_covariance) {
  const NetworkCamera& camera = (*layout.cameras)[index];
  BundleResult out;
  BundleDetails& details = out.details;
  CalibrationResult& cal = out.calibration;
  cal.camera_id = camera.initial.id;
  cal.method = "network";
  cal.camera = blocks.cameras[index].to_camera(layout.starts[index]);
  cal.clock_offset_s = blocks.cameras[index].clock[0];
  cal.parameters = layout.free[index];
  details.free = layout.free[index];
  details.chi2 = stats.chi2;
  details.dof = stats.dof;
  details.variance_factor = stats.variance_factor;
  details.iterations = stats.iterations;
  details.solves.resize(static_cast<std::size_t>(n_solves));
  details.rank_deficient = cov.rank_deficient;
  details.outlier_threshold_sigma = test.threshold[index];
  details.pixel_sigma_px = camera.options.pixel_sigma_px;
  details.covariance_scaled = scale_covariance;
  if (layout.setups[index].is_free(CameraParameter::clock_offset))
    details.clock_offset_s = cal.clock_offset_s;
  camera_covariance(layout, index, cov, stats, scale_covariance, &out);
  camera_residuals(mine, test, dropped, selection, &out);
  finish_bundle_result(max_speed(layout, index), camera.options.correlation_warning, &out);
  return out;
}

/// `from`'s PPK outliers, their priors dropped from `selection` and their test figures copied to
/// `points`; returns their indices.
std::vector<std::size_t> carry_ppk_outliers(const NetworkResult& from, NetworkSelection* selection,
                                            std::vector<NetworkPointResult>* points) {
  std::vector<std::size_t> flagged;
  for (std::size_t k = 0; k < from.points.size(); ++k) {
    const NetworkPointResult& was = from.points[k];
    NetworkPointResult& p = (*points)[k];
    p.ppk_test_d2 = was.ppk_test_d2, p.ppk_test_dof = was.ppk_test_dof;
    if (!was.ppk_outlier) continue;
    p.ppk_outlier = true;
    selection->prior[k] = 0;
    flagged.push_back(k);
  }
  return flagged;
}

/// Per observation (`n` of them): flagged as an image outlier in `from`.
std::vector<bool> image_outliers_of(const NetworkResult& from, std::size_t n) {
  std::vector<bool> flagged(n, false);
  for (std::size_t c = 0; c < from.cameras.size(); ++c)
    for (std::size_t j = 0; j < from.cameras[c].outlier.size(); ++j)
      if (from.cameras[c].outlier[j]) flagged[from.camera_observations[c][j]] = true;
  return flagged;
}

/// The independent looks at the PPK error of the chained fixes in the final solve.
void count_ppk_looks(const NetworkLayout& layout, const NetworkSelection& selection,
                     NetworkStatistics* stats) {
  std::vector<double> t;
  for (std::size_t k : layout.gm_chain)
    if (selection.prior[k]) t.push_back((*layout.points)[k].time_s);
  if (t.empty()) return;
  const Eigen::Vector3d looks = gauss_markov_looks(layout.ppk, t);
  stats->ppk_looks_h = looks.x(), stats->ppk_looks_v = looks.z();
}

/// The network-wide warnings on the PPK outliers, the cameras calibrated alone and a datum on few
/// independent PPK looks.
void add_network_warnings(const NetworkLayout& layout, const NetworkStatistics& stats,
                          const std::optional<PpkErrorEstimate>& estimate,
                          std::vector<std::string>* warnings) {
  const double looks = std::min(stats.ppk_looks_h, stats.ppk_looks_v);
  if (!layout.gm_chain.empty() && looks < kFewPpkLooks)
    warnings->push_back("the PPK fixes give " + format_number("%.1f", stats.ppk_looks_h) +
                        " horizontal and " + format_number("%.1f", stats.ppk_looks_v) +
                        " vertical independent looks at their slow error (fewer than " +
                        format_number("%g", kFewPpkLooks) +
                        "): the datum rests on few samples; more control poles, camera stations surveyed or "
                        "ascents spread over more time would lower the error");
  if (estimate && (estimate->gm_sd_held_h || estimate->gm_sd_held_v)) {
    const bool both = estimate->gm_sd_held_h && estimate->gm_sd_held_v;
    warnings->push_back("the PPK record (" + format_number("%.0f", estimate->record_s) +
                        " s) is shorter than 4 correlation times: the " +
                        (both                     ? "horizontal and vertical"
                         : estimate->gm_sd_held_h ? "horizontal"
                                                  : "vertical") +
                        " Gauss–Markov sd cannot be told from τ; it was held at the .pos sd and τ estimated "
                        "with it (docs/optimisation.md \"Correlated PPK errors — estimation\")");
  }
  if (estimate)
    for (std::size_t c = 0; c < estimate->image_scale.size(); ++c) {
      const double s = estimate->image_scale[c], sd = estimate->image_scale_sd[c];
      const double stated = (*layout.cameras)[c].options.pixel_sigma_px / s;
      if (c < estimate->image_scale_held.size() && estimate->image_scale_held[c]) {
        warnings->push_back(
            (*layout.cameras)[c].initial.id +
            ": its centroid σ is not determined by this mission (the PPK fixes' own error, projected, "
            "hides it): held at the stated " +
            format_number("%.3g", stated) + " px");
        continue;
      }
      if (sd <= kUndeterminedImageSigma * s) continue;  // determined (a NaN σ is not)
      warnings->push_back((*layout.cameras)[c].initial.id +
                          ": its centroid σ is poorly determined by this mission (" +
                          format_number("%.3g", stated * s) + " ± " + format_number("%.2g", stated * sd) +
                          " px): the PPK fixes' own error is not told from it; its calibration σ carry it");
    }
  if (!stats.ppk_outliers.empty())
    warnings->push_back(
        std::to_string(stats.ppk_outliers.size()) +
        " epochs disagree with their PPK fix beyond the whitened test; their priors were dropped");
  for (std::size_t c : stats.cameras_alone)
    warnings->push_back((*layout.cameras)[c].initial.id +
                        " shares no epoch with another camera: calibrated from its own epochs alone");
}

/// The whole adjustment with the cameras' centroids at the σ `cameras` state (network_adjust).
NetworkResult adjust(const std::vector<NetworkCamera>& cameras, const std::vector<NetworkPoint>& points,
                     const std::vector<NetworkObservation>& observations, const NetworkOptions& options,
                     const NetworkResult* outliers_of = nullptr) {
  const NetworkLayout layout = make_network_layout(cameras, points, observations, options.ppk_error);
  // Under a correlated model the robust solve and the outlier tests run on its white approximation
  // (each fix under its whole covariance), the final solve on the model (network_gauss_newton.hpp).
  const bool correlated = !layout.gm_chain.empty();
  const NetworkLayout white = correlated ? white_approximation(layout) : NetworkLayout{};
  const NetworkLayout& separating = correlated ? white : layout;
  NetworkParameterBlocks blocks = starting_blocks(layout);
  NetworkSelection selection{
      std::vector<char>(observations.size(), 1), std::vector<char>(points.size(), 1), {}, {}};
  NetworkResult out;
  out.ppk_error = options.ppk_error;
  out.gauss_markov_states = static_cast<int>(layout.gm_chain.size());
  NetworkStatistics& stats = out.statistics;
  out.points.resize(points.size());

  // 1. Robust solve, every prior in; single-view weights at the starting cameras.
  refresh_single_view(separating, blocks, &selection);
  NetworkCeresProblem problem(separating, &blocks, selection);
  stats.iterations += problem.solve(options.loss, options.loss_scale,
                                    options.resolve_without_outliers ? kSeparatingTolerance : kFinalTolerance,
                                    options.max_iterations, options.num_threads);
  int n_solves = 1;

  // 2. PPK outliers (multi-ray epochs), then image outliers (the bundle's rule, per camera); the
  // image outliers of the robust solution are the ones listed (and dropped).
  // With `outliers_of`, its outliers instead: tested at the σ it weighed by.
  stats.ppk_outliers = outliers_of ? carry_ppk_outliers(*outliers_of, &selection, &out.points)
                                   : flag_ppk_outliers(separating, blocks, options.ppk_outlier_probability,
                                                       &selection, &out.points);
  ImageOutlierTest test = test_image_observations(separating, blocks, selection, options.outlier_threshold);
  if (outliers_of) test.outlier = image_outliers_of(*outliers_of, observations.size());
  const std::vector<bool> dropped = test.outlier;
  for (bool flagged : dropped) stats.image_outliers += flagged ? 1 : 0;

  // 3. Plain least squares without them, weights at the robust solution as the per-camera bundle.
  if (options.resolve_without_outliers) drop_image_outliers(layout, test, &selection);
  // Under an estimated model the final solve is on the estimate, white or correlated.
  NetworkLayout estimated;
  std::vector<NetworkCamera> estimated_cameras;  // `estimated` points into it
  if (options.estimate_ppk_error) {
    out.ppk_estimate = estimate_ppk_error_model(separating, blocks, selection,
                                                {options.estimate_image_sigma, options.estimate_white_only});
    out.ppk_error = out.ppk_estimate->model;
    // Each camera's lamp centroids at the σ estimated with the model (pole picks keep their own).
    estimated_cameras = cameras;
    for (std::size_t c = 0; c < cameras.size(); ++c)
      estimated_cameras[c].options.pixel_sigma_px *= out.ppk_estimate->image_scale[c];
    estimated = make_network_layout(estimated_cameras, points, observations, out.ppk_error);
    out.gauss_markov_states = static_cast<int>(estimated.gm_chain.size());
    blocks.gm.assign(estimated.gm_chain.size(), {0.0, 0.0, 0.0});
  }
  const NetworkLayout& final_layout = options.estimate_ppk_error ? estimated : layout;
  if (correlated || options.estimate_ppk_error) {
    refresh_single_view(final_layout, blocks, &selection);
    stats.iterations +=
        network_gauss_newton(final_layout, &blocks, selection, kFinalTolerance, options.max_iterations);
    ++n_solves;
    test = test_image_observations(final_layout, blocks, selection, options.outlier_threshold);
  } else if (options.resolve_without_outliers) {
    refresh_single_view(final_layout, blocks, &selection);
    problem.select(selection);
    stats.iterations += problem.solve(RobustLoss::none, options.loss_scale, kFinalTolerance,
                                      options.max_iterations, options.num_threads);
    ++n_solves;
    test = test_image_observations(final_layout, blocks, selection, options.outlier_threshold);
  }

  // 4. Joint covariance (Schur complement) and the points', single-view weights at the solution.
  refresh_single_view(final_layout, blocks, &selection);
  const NetworkCovariance cov =
      network_covariance(final_layout, blocks, selection, scene_distance(final_layout),
                         max_speed(final_layout), options.rank_tolerance);
  fill_statistics(final_layout, selection, cov, &stats);
  count_ppk_looks(final_layout, selection, &stats);
  const bool scaled = options.scale_covariance && std::isfinite(stats.variance_factor);
  if (cov.joint.size() > 0)
    out.joint_covariance = scaled ? Eigen::MatrixXd(cov.joint * stats.variance_factor) : cov.joint;
  out.joint_offset = final_layout.offset;
  fill_point_results(final_layout, selection, cov, &out.points);
  if (stats.float_epochs_used > 0)
    out.float_epochs = float_epoch_contribution(final_layout, blocks, selection, cov, stats.float_epochs_used,
                                                options.rank_tolerance);
  out.warnings = cov.warnings;
  add_datum_floor(final_layout, blocks, selection, options, scaled ? stats.variance_factor : 1.0, &out);
  add_network_warnings(final_layout, stats, out.ppk_estimate, &out.warnings);

  // 5. Per camera.
  out.camera_observations.resize(cameras.size());
  for (std::size_t i = 0; i < observations.size(); ++i)
    out.camera_observations[observations[i].camera].push_back(i);
  for (std::size_t c = 0; c < cameras.size(); ++c)
    out.cameras.push_back(camera_result(final_layout, blocks, c, out.camera_observations[c], test, dropped,
                                        selection, cov, stats, n_solves, options.scale_covariance));
  return out;
}

/// An estimated image scale beyond this factor of the stated σ (either way) means the outlier tests
/// weighed the rays wrongly: the adjustment runs again at the estimated σ.
constexpr double kImageScaleRetest = 1.5;

/// The adjustment, and once more at the estimated image σ when it is far from the stated one.
NetworkResult estimate_image_scales(const std::vector<NetworkCamera>& cameras,
                                    const std::vector<NetworkPoint>& points,
                                    const std::vector<NetworkObservation>& observations,
                                    const NetworkOptions& options) {
  NetworkResult first = adjust(cameras, points, observations, options);
  if (!first.ppk_estimate || !options.estimate_image_sigma) return first;
  const std::vector<double>& scale = first.ppk_estimate->image_scale;
  const bool far = std::any_of(scale.begin(), scale.end(),
                               [](double s) { return s > kImageScaleRetest || s < 1 / kImageScaleRetest; });
  if (!far) return first;
  // The outlier tests (robust solve, PPK and image outliers) weighed each ray by the stated σ: with
  // centroids 5× noisier than stated every ray looks 5× sharper than it is, and fixes and pixels that
  // fit as well as the rest are dropped. Once more from the start with each camera's centroids at
  // their estimated σ; the scales the second estimate finds are relative to those.
  // A camera whose scale sits on a bound of the estimate's box keeps its stated σ: the second estimate
  // then searches the same box again rather than one beyond it.
  std::vector<NetworkCamera> estimated = cameras;
  std::vector<double> applied(cameras.size(), 1.0);
  for (std::size_t c = 0; c < cameras.size(); ++c)
    if (scale[c] > kLowestImageScale * kImageScaleRetest && scale[c] < kHighestImageScale / kImageScaleRetest)
      applied[c] = scale[c], estimated[c].options.pixel_sigma_px *= scale[c];
  NetworkResult again = adjust(estimated, points, observations, options);
  PpkErrorEstimate& e = *again.ppk_estimate;
  for (std::size_t c = 0; c < cameras.size(); ++c)
    e.image_scale[c] *= applied[c], e.image_scale_sd[c] *= applied[c];
  e.evaluations += first.ppk_estimate->evaluations;
  return again;
}

/// The network once more with each camera whose residuals repeat themselves in time weighed by
/// σ·√F (image_time_correlation.hpp), its σ then held and the PPK model estimated again; the image
/// scales reported stay the centroids' own scatter (the estimate before), and so do the outliers.
NetworkResult weigh_correlated_images(const std::vector<NetworkCamera>& cameras,
                                      const std::vector<NetworkPoint>& points,
                                      const std::vector<NetworkObservation>& observations,
                                      const NetworkOptions& options, NetworkResult estimated) {
  const std::vector<double> factor = image_time_correlation(estimated, points, observations);
  if (std::all_of(factor.begin(), factor.end(), [](double f) { return f == 1; })) {
    estimated.ppk_estimate->image_time_factor = factor;
    return estimated;
  }
  const PpkErrorEstimate& e = *estimated.ppk_estimate;
  std::vector<NetworkCamera> weighed = cameras;
  for (std::size_t c = 0; c < cameras.size(); ++c)
    weighed[c].options.pixel_sigma_px *= e.image_scale[c] * std::sqrt(factor[c]);
  NetworkOptions held = options;
  held.estimate_image_sigma = false;
  // The outliers stay the estimate's: they were tested against the centroids' own σ, which is the
  // scatter of one residual however its errors repeat in time; at σ·√F the tests would pass
  // residuals √F times larger.
  NetworkResult out = adjust(weighed, points, observations, held, &estimated);
  PpkErrorEstimate& w = *out.ppk_estimate;
  w.image_scale = e.image_scale;
  w.image_scale_sd = e.image_scale_sd;
  w.image_scale_held = e.image_scale_held;
  w.image_time_factor = factor;
  w.evaluations += e.evaluations;
  // The outliers are the estimate's tests (at the σ it weighed by, σ̂ or the stated σ): the cut-off
  // they met is the estimate's. The whitened norms beside them are this solve's, at σ̂·√F.
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    out.cameras[c].details.time_correlation_factor = factor[c];
    out.cameras[c].details.outlier_threshold_sigma = estimated.cameras[c].details.outlier_threshold_sigma;
  }
  // This solve held the image σ (its scales 1, their σ NaN), so it says nothing of how well the
  // mission determined them: the estimate's warnings on that replace its own.
  const auto on_centroid_sigma = [](const std::string& w) {
    return w.find(": its centroid σ is") != std::string::npos;
  };
  out.warnings.erase(std::remove_if(out.warnings.begin(), out.warnings.end(), on_centroid_sigma),
                     out.warnings.end());
  for (const std::string& warning : estimated.warnings)
    if (on_centroid_sigma(warning)) out.warnings.push_back(warning);
  return out;
}

}  // namespace

NetworkResult network_adjust(const std::vector<NetworkCamera>& cameras,
                             const std::vector<NetworkPoint>& points,
                             const std::vector<NetworkObservation>& observations,
                             const NetworkOptions& options) {
  check_network_input(cameras, points, observations);
  NetworkResult estimated = estimate_image_scales(cameras, points, observations, options);
  if (!estimated.ppk_estimate || !options.estimate_image_sigma || !options.image_time_correlation)
    return estimated;
  return weigh_correlated_images(cameras, points, observations, options, std::move(estimated));
}

}  // namespace rangecal
