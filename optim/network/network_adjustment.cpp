#include "optim/network/network_adjustment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "optim/bundle/bundle_diagnostics.hpp"
#include "optim/network/network_ceres_problem.hpp"
#include "optim/network/network_covariance.hpp"
#include "optim/network/network_input_checks.hpp"
#include "optim/network/network_outliers.hpp"
#include "optim/network/network_parameters.hpp"

namespace rangecal {
namespace {

using Eigen::Vector3d;

// ---------------------------------------------------------------------------------------------
// Set-up.

/// Number of cameras with a used observation of each point.
std::vector<int> cameras_per_point(const NetworkLayout& l, const NetworkSelection& sel) {
  std::vector<int> n(l.by_point.size(), 0);
  for (std::size_t k = 0; k < l.by_point.size(); ++k) {
    std::vector<std::size_t> seen;
    for (std::size_t i : l.by_point[k])
      if (sel.observation[i]) seen.push_back((*l.observations)[i].camera);
    std::sort(seen.begin(), seen.end());
    n[k] = static_cast<int>(std::unique(seen.begin(), seen.end()) - seen.begin());
  }
  return n;
}

/// A point without a prior needs two cameras' rays; a point without observations leaves the solve.
void drop_undetermined_points(const NetworkLayout& l, NetworkSelection* sel) {
  const std::vector<int> n = cameras_per_point(l, *sel);
  for (std::size_t k = 0; k < n.size(); ++k) {
    if (n[k] == 0) sel->prior[k] = 0;
    if (!sel->prior[k] && n[k] < 2)
      for (std::size_t i : l.by_point[k]) sel->observation[i] = 0;
  }
}

// ---------------------------------------------------------------------------------------------
// Solving (network_ceres_problem.hpp).

/// Relative tolerances (Ceres' function and parameter tolerance) of a solve whose result is the
/// network's, and of the robust solve that only separates outliers before the final least-squares
/// solve starts from it. Under a robust loss the iterations converge linearly (each step ~1/5 to
/// 1/30 of the last on 8 cameras × 5,000 epochs); after the relative step falls below 1e-6 the
/// remaining steps add up to 1.6 mm in norm over all 15,000 point coordinates and the cameras —
/// ~10 µm a point, 0.001 px — and would cost six more iterations (docs/performance.md).
constexpr double kFinalTolerance = 1e-12;
constexpr double kSeparatingTolerance = 1e-6;

// ---------------------------------------------------------------------------------------------
// Results.

double scene_distance(const NetworkLayout& l) {
  double sum = 0;
  int n = 0;
  for (const NetworkObservation& o : *l.observations)
    sum += (l.starts[o.camera].pose.center() - (*l.points)[o.point].prior_enu).norm(), ++n;
  return std::max(1.0, n > 0 ? sum / n : 1.0);
}

double max_speed(const NetworkLayout& l, std::size_t camera) {
  double v = 0;
  for (const NetworkObservation& o : *l.observations)
    if (camera == static_cast<std::size_t>(-1) || o.camera == camera) v = std::max(v, o.velocity.norm());
  return v;
}

void count_epochs(const NetworkLayout& l, const NetworkSelection& sel, NetworkStatistics* st) {
  const std::vector<int> n = cameras_per_point(l, sel);
  for (std::size_t k = 0; k < n.size(); ++k) {
    const NetworkPoint& p = (*l.points)[k];
    if (p.control_pole || n[k] == 0) continue;
    (n[k] == 1 ? st->epochs_seen_by_1 : n[k] == 2 ? st->epochs_seen_by_2 : st->epochs_seen_by_3_or_more)++;
    if (p.quality >= 2) ++st->float_epochs_used;
  }
  // Cameras sharing no used epoch (or pole) with another camera.
  std::vector<char> shares(l.starts.size(), 0);
  for (std::size_t k = 0; k < n.size(); ++k) {
    if (n[k] < 2) continue;
    for (std::size_t i : l.by_point[k])
      if (sel.observation[i]) shares[(*l.observations)[i].camera] = 1;
  }
  for (std::size_t c = 0; c < shares.size(); ++c)
    if (!shares[c]) st->cameras_alone.push_back(c);
}

/// σ of each camera's free parameters (free order) from `cov`'s joint covariance (a-priori); an
/// empty vector for every camera when it is rank-deficient.
std::vector<Eigen::VectorXd> camera_sigmas(const NetworkLayout& l, const NetworkCovariance& cov) {
  std::vector<Eigen::VectorXd> out(l.setups.size());
  if (cov.rank_deficient || cov.joint.size() == 0) return out;
  for (std::size_t c = 0; c < out.size(); ++c)
    out[c] = cov.joint.diagonal().segment(l.offset[c], l.setups[c].n_free).cwiseSqrt();
  return out;
}

/// The float epochs' share: the covariance again at the same solution with their priors and image
/// observations left out (a linearised "without them", no second solve).
FloatEpochContribution float_epoch_contribution(const NetworkLayout& l, const NetworkParameterBlocks& b,
                                                const NetworkSelection& sel, const NetworkCovariance& with,
                                                int epochs, double rank_tolerance) {
  FloatEpochContribution f;
  f.epochs = epochs;
  f.sigma_with = camera_sigmas(l, with);
  NetworkSelection without = sel;
  for (std::size_t k = 0; k < l.by_point.size(); ++k) {
    const NetworkPoint& p = (*l.points)[k];
    if (p.control_pole || p.quality < 2) continue;
    without.prior[k] = 0;
    for (std::size_t i : l.by_point[k]) without.observation[i] = 0;
  }
  drop_undetermined_points(l, &without);
  refresh_single_view(l, b, &without);
  f.sigma_without =
      camera_sigmas(l, network_covariance(l, b, without, scene_distance(l),
                                          max_speed(l, static_cast<std::size_t>(-1)), rank_tolerance));
  return f;
}

/// The datum floor: the joint covariance again at the same solution and selection with every image
/// σ divided by `factor` (single-view weights recomputed with it), scaled as the network's.
Eigen::MatrixXd datum_floor_covariance(const NetworkLayout& l, const NetworkParameterBlocks& b,
                                       NetworkSelection sel, double factor, double scale,
                                       double rank_tolerance) {
  NetworkLayout sharp = l;
  sharp.pixel_sigma_scale = 1 / factor;
  refresh_single_view(sharp, b, &sel);
  const NetworkCovariance cov = network_covariance(
      sharp, b, sel, scene_distance(l), max_speed(l, static_cast<std::size_t>(-1)), rank_tolerance);
  if (cov.rank_deficient || cov.joint.size() == 0) return {};
  return cov.joint * scale;
}

/// Camera c's result: its marginal of the joint covariance, residuals and flags of its observations.
BundleResult camera_result(const NetworkLayout& l, const NetworkParameterBlocks& b, std::size_t c,
                           const std::vector<std::size_t>& mine, const ImageOutlierTest& test,
                           const std::vector<bool>& dropped, const NetworkSelection& sel,
                           const NetworkCovariance& cov, const NetworkStatistics& st, int n_solves) {
  const NetworkCamera& nc = (*l.cameras)[c];
  BundleResult out;
  BundleDetails& d = out.details;
  CalibrationResult& cal = out.calibration;
  cal.camera_id = nc.initial.id;
  cal.method = "network";
  cal.camera = b.cameras[c].to_camera(l.starts[c]);
  cal.clock_offset_s = b.cameras[c].clock[0];
  cal.parameters = l.free[c];
  d.free = l.free[c];
  d.chi2 = st.chi2, d.dof = st.dof, d.variance_factor = st.variance_factor;
  d.iterations = st.iterations;
  d.solves.resize(static_cast<std::size_t>(n_solves));
  d.rank_deficient = cov.rank_deficient;
  d.outlier_threshold_sigma = test.threshold[c];
  d.pixel_sigma_px = nc.options.pixel_sigma_px;
  d.covariance_scaled = nc.options.scale_covariance;
  if (l.setups[c].is_free(CameraParameter::clock_offset)) d.clock_offset_s = cal.clock_offset_s;
  const int p = l.setups[c].n_free;
  if (!cov.rank_deficient && cov.joint.size() > 0) {
    out.covariance_unscaled = cov.joint.block(l.offset[c], l.offset[c], p, p);
    out.covariance_scaled =
        out.covariance_unscaled * (std::isfinite(st.variance_factor) ? st.variance_factor : 1.0);
    cal.covariance = nc.options.scale_covariance ? out.covariance_scaled : out.covariance_unscaled;
    d.sigma_unscaled = out.covariance_unscaled.diagonal().cwiseSqrt();
    d.sigma_scaled = out.covariance_scaled.diagonal().cwiseSqrt();
    Eigen::Matrix3d cc = Eigen::Matrix3d::Zero();
    for (int a = 0; a < 3; ++a)
      for (int e = 0; e < 3; ++e) {
        const int ia = cal.parameter_index(kCenterParameters[a]),
                  ie = cal.parameter_index(kCenterParameters[e]);
        if (ia >= 0 && ie >= 0) cc(a, e) = cal.covariance(ia, ie);
      }
    cal.center_covariance_m2 = cc;
  } else {
    cal.warnings = cov.warnings;
  }
  double s2 = 0, s1 = 0, mx = 0;
  int nu = 0;
  for (std::size_t j = 0; j < mine.size(); ++j) {
    const std::size_t i = mine[j];
    out.residual_px.push_back(test.residual_px[i]);
    out.whitened_norm.push_back(test.whitened_norm[i]);
    out.outlier.push_back(dropped[i]);
    if (dropped[i]) cal.rejected.push_back(j), d.outliers.push_back(j);
    if (!sel.observation[i]) continue;
    const double e = test.residual_px[i].norm();
    s2 += e * e, s1 += e, mx = std::max(mx, e), ++nu;
  }
  cal.reprojection.n_used = nu;
  cal.reprojection.n_rejected = static_cast<int>(mine.size()) - nu;
  if (nu > 0)
    cal.reprojection.rms_px = std::sqrt(s2 / nu), cal.reprojection.mean_px = s1 / nu,
    cal.reprojection.max_px = mx;
  for (std::string& w : poorly_determined_warnings(cal, max_speed(l, c), nc.options.correlation_warning))
    cal.warnings.push_back(std::move(w));
  for (std::string& w : fit_warnings(d)) cal.warnings.push_back(std::move(w));
  out.chi2 = d.chi2, out.dof = d.dof, out.variance_factor = d.variance_factor;
  out.rank_deficient = d.rank_deficient, out.iterations = d.iterations;
  return out;
}

}  // namespace

NetworkResult network_adjust(const std::vector<NetworkCamera>& cameras,
                             const std::vector<NetworkPoint>& points,
                             const std::vector<NetworkObservation>& obs, const NetworkOptions& opt) {
  check_network_input(cameras, points, obs);
  const NetworkLayout l = make_network_layout(cameras, points, obs);
  NetworkParameterBlocks b = starting_blocks(l);
  NetworkSelection sel{std::vector<char>(obs.size(), 1), std::vector<char>(points.size(), 1), {}, {}};
  NetworkResult out;
  NetworkStatistics& st = out.statistics;
  out.points.resize(points.size());
  int n_solves = 0;

  // 1. Robust solve, every prior in; single-view weights at the starting cameras.
  refresh_single_view(l, b, &sel);
  NetworkCeresProblem problem(l, &b, sel);
  st.iterations += problem.solve(opt.loss, opt.loss_scale,
                                 opt.resolve_without_outliers ? kSeparatingTolerance : kFinalTolerance,
                                 opt.max_iterations, opt.num_threads),
      ++n_solves;

  // 2. PPK outliers (multi-ray epochs), then image outliers (the bundle's rule, per camera).
  st.ppk_outliers = flag_ppk_outliers(l, b, opt.ppk_outlier_probability, &sel, &out.points);
  ImageOutlierTest test = test_image_observations(l, b, sel, opt.outlier_threshold);
  std::vector<bool> dropped(obs.size(), false);

  // 3. Plain least squares without them.
  if (opt.resolve_without_outliers) {
    for (std::size_t i = 0; i < obs.size(); ++i)
      if (test.outlier[i]) sel.observation[i] = 0, dropped[i] = true;
    drop_undetermined_points(l, &sel);
    for (std::size_t c = 0; c < cameras.size(); ++c) {
      int used = 0;
      for (std::size_t i = 0; i < obs.size(); ++i) used += obs[i].camera == c && sel.observation[i] ? 1 : 0;
      if (2 * used < l.setups[c].n_free)
        throw_calibration_error("network", cameras[c].initial.id +
                                               ": after rejecting outliers too few points remain (" +
                                               std::to_string(used) + ")");
    }
    refresh_single_view(l, b, &sel);  // weights at the robust solution, as the per-camera bundle
    problem.select(sel);
    st.iterations +=
        problem.solve(RobustLoss::none, opt.loss_scale, kFinalTolerance, opt.max_iterations, opt.num_threads),
        ++n_solves;
    test = test_image_observations(l, b, sel, opt.outlier_threshold);
  } else {
    dropped = test.outlier;
  }
  for (bool d : dropped) st.image_outliers += d ? 1 : 0;

  // 4. Joint covariance (Schur complement) and the points', single-view weights at the solution.
  refresh_single_view(l, b, &sel);
  const NetworkCovariance cov =
      network_covariance(l, b, sel, scene_distance(l), max_speed(l, static_cast<std::size_t>(-1)),
                         cameras.front().options.rank_tolerance);
  st.chi2 = cov.chi2;
  st.dof = cov.residuals - cov.parameters;
  st.variance_factor = st.dof > 0 ? st.chi2 / st.dof : std::numeric_limits<double>::quiet_NaN();
  st.rank_deficient = cov.rank_deficient;
  count_epochs(l, sel, &st);
  const bool scaled = cameras.front().options.scale_covariance && std::isfinite(st.variance_factor);
  if (cov.joint.size() > 0)
    out.joint_covariance = scaled ? Eigen::MatrixXd(cov.joint * st.variance_factor) : cov.joint;
  out.joint_offset = l.offset;
  const std::vector<int> seen = cameras_per_point(l, sel);
  for (std::size_t k = 0; k < points.size(); ++k) {
    NetworkPointResult& pr = out.points[k];
    pr.enu = cov.point_enu[k];
    pr.correction = pr.enu - points[k].prior_enu;
    pr.cov = cov.point_cov[k];
    pr.cameras = seen[k];
    pr.prior_used = sel.prior[k] != 0;
    pr.used = pr.prior_used || seen[k] > 0;
  }
  if (st.float_epochs_used > 0)
    out.float_epochs = float_epoch_contribution(l, b, sel, cov, st.float_epochs_used,
                                                cameras.front().options.rank_tolerance);
  out.warnings = cov.warnings;
  if (opt.datum_floor_image_factor > 0 && out.joint_covariance.size() > 0) {
    out.datum_floor_covariance =
        datum_floor_covariance(l, b, sel, opt.datum_floor_image_factor, scaled ? st.variance_factor : 1.0,
                               cameras.front().options.rank_tolerance);
    if (out.datum_floor_covariance.size() > 0)
      out.datum_floor_image_factor = opt.datum_floor_image_factor;
    else
      out.warnings.push_back("the datum floor (images " + format_number("%g", opt.datum_floor_image_factor) +
                             "x sharper) is rank-deficient at the rank tolerance: not computed");
  }
  if (!st.ppk_outliers.empty())
    out.warnings.push_back(
        std::to_string(st.ppk_outliers.size()) +
        " epochs disagree with their PPK fix beyond the whitened test; their priors were dropped");
  for (std::size_t c : st.cameras_alone)
    out.warnings.push_back(cameras[c].initial.id +
                           " shares no epoch with another camera: calibrated from its own epochs alone");

  // 5. Per camera.
  out.camera_observations.resize(cameras.size());
  for (std::size_t i = 0; i < obs.size(); ++i) out.camera_observations[obs[i].camera].push_back(i);
  for (std::size_t c = 0; c < cameras.size(); ++c)
    out.cameras.push_back(
        camera_result(l, b, c, out.camera_observations[c], test, dropped, sel, cov, st, n_solves));
  return out;
}

}  // namespace rangecal
