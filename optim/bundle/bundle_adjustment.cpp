#include "optim/bundle/bundle_adjustment.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "config/error.hpp"
#include "optim/bundle/bundle_covariance.hpp"
#include "optim/bundle/bundle_diagnostics.hpp"
#include "optim/bundle/bundle_input_checks.hpp"
#include "optim/bundle/bundle_parameters.hpp"
#include "optim/bundle/correlated_ppk_covariance.hpp"
#include "optim/bundle/reprojection_cost.hpp"
#include "optim/bundle/reprojection_cost_function.hpp"
#include "optim/estimation/center_covariance.hpp"
#include "optim/estimation/reprojection_stats.hpp"
#include "optim/estimation/robust_scale.hpp"

namespace rangecal {

namespace {

using Eigen::Matrix2d;
using Eigen::MatrixXd;
using Eigen::Vector2d;

using PrincipalPointCost = ceres::AutoDiffCostFunction<PrincipalPointPrior, 2, kIntrinsicsBlockSize>;
using CenterCost = ceres::AutoDiffCostFunction<CenterPrior, 3, kPoseBlockSize>;

// ---------------------------------------------------------------------------------------------
// Set-up.

ceres::Manifold* subset_manifold(const bool* free, int size) {
  std::vector<int> constant;
  for (int i = 0; i < size; ++i)
    if (!free[i]) constant.push_back(i);
  if (constant.empty() || static_cast<int>(constant.size()) == size) return nullptr;
  return new ceres::SubsetManifold(size, constant);
}

// ---------------------------------------------------------------------------------------------
// Solving.

/// The Ceres problem over the used observations with fixed weights W, the priors in use, and the
/// parameters that are not free held constant.
void build_problem(BundleParameterBlocks& st, const Camera& base, const std::vector<BundleObservation>& obs,
                   const std::vector<char>& used, const std::vector<Matrix2d>& W, const BundleSetup& setup,
                   const BundleOptions& opt, RobustLoss loss, ceres::Problem* problem) {
  ceres::LossFunction* lf = new_robust_loss(loss, opt.loss_scale);
  bool lf_used = false;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    if (!used[i]) continue;
    auto* cost = new ReprojectionCostFunction(ReprojectionResidual{
        obs[i].world, obs[i].velocity, obs[i].pixel, W[i], st.R0, base.intr.dx_mm, base.intr.dy_mm});
    problem->AddResidualBlock(cost, lf, st.intr, st.dist, st.pose, st.clock);
    lf_used = lf_used || lf;
  }
  if (lf && !lf_used) delete lf;
  if (setup.principal_point_prior)
    problem->AddResidualBlock(new PrincipalPointCost(new PrincipalPointPrior{
                                  opt.priors.principal_point_px, opt.priors.principal_point_sigma_px}),
                              nullptr, st.intr);
  if (setup.center_prior)
    problem->AddResidualBlock(
        new CenterCost(new CenterPrior{opt.priors.center_enu_m, opt.priors.center_sigma_m}), nullptr,
        st.pose);
  int offset = 0;
  for (int b = 0; b < 4; ++b) {
    const bool* fr = setup.free.data() + offset;
    const int size = kBundleBlockSizes[static_cast<std::size_t>(b)];
    const int nf = static_cast<int>(std::count(fr, fr + size, true));
    if (nf == 0)
      problem->SetParameterBlockConstant(st.block(b));
    else if (ceres::Manifold* m = subset_manifold(fr, size))
      problem->SetManifold(st.block(b), m);
    offset += size;
  }
}

/// One Levenberg–Marquardt solve over the used points with fixed weights; the rotation is
/// re-based afterwards.
BundleSolve solve(BundleParameterBlocks& st, const Camera& base, const std::vector<BundleObservation>& obs,
                  const std::vector<char>& used, const std::vector<Matrix2d>& W, const BundleSetup& setup,
                  const BundleOptions& opt, RobustLoss loss) {
  ceres::Problem problem;
  build_problem(st, base, obs, used, W, setup, opt, loss, &problem);
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = opt.max_iterations;
  so.function_tolerance = 1e-14;
  so.gradient_tolerance = 1e-16;
  so.parameter_tolerance = 1e-14;
  so.num_threads = 1;  // deterministic and cheap: ≤ 18 parameters
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (!summary.IsSolutionUsable() || !std::isfinite(summary.final_cost))
    throw_calibration_error("bundle", "Levenberg–Marquardt failed: " + summary.message);
  st.rebase_rotation(base);
  BundleSolve s;
  s.loss = loss;
  s.iterations = static_cast<int>(summary.iterations.size());
  return s;
}

// ---------------------------------------------------------------------------------------------
// Outliers.

/// Residuals of every observation at `c` (clock offset δ), their whitened norms, and the outlier
/// flags: ‖W·e‖ above the robust threshold over the used points (optim/estimation/robust_scale.hpp).
/// Returns the threshold.
double flag_outliers(const Camera& c, double clock_offset_s, const std::vector<BundleObservation>& obs,
                     const std::vector<char>& used, const std::vector<Matrix2d>& W, const BundleOptions& opt,
                     BundleResult* out) {
  const std::size_t n = obs.size();
  out->residual_px.assign(n, Vector2d::Zero());
  out->whitened_norm.assign(n, 0);
  std::vector<double> norms;
  for (std::size_t i = 0; i < n; ++i) {
    Vector2d uv;
    if (!project(c, observed_world_point(obs[i], clock_offset_s), &uv))
      uv.setConstant(std::numeric_limits<double>::infinity());
    out->residual_px[i] = uv - obs[i].pixel;
    out->whitened_norm[i] = (W[i] * out->residual_px[i]).norm();
    if (used[i]) norms.push_back(out->whitened_norm[i]);
  }
  const double thr = robust_outlier_threshold(opt.outlier_threshold, std::move(norms));
  out->outlier.assign(n, false);
  for (std::size_t i = 0; i < n; ++i) out->outlier[i] = !(out->whitened_norm[i] <= thr);
  return thr;
}

}  // namespace

BundleResult bundle_adjust(const Camera& initial, const std::vector<BundleObservation>& obs,
                           const BundleOptions& opt) {
  const BundleSetup setup = bundle_setup(opt);
  check_bundle_input(initial, obs, setup, opt);
  const std::size_t n = obs.size();
  const double max_speed = bundle_max_speed(obs);
  const Camera start = bundle_starting_camera(initial, setup, opt);

  BundleResult out;
  BundleDetails& d = out.details;
  BundleParameterBlocks st = BundleParameterBlocks::from_camera(start, opt.initial_clock_offset_s);
  std::vector<char> used(n, 1);

  // 1. Robust solve with weights at the starting camera.
  std::vector<Matrix2d> W = whitening_matrices(start, obs, opt.pixel_sigma_px);
  d.solves.push_back(solve(st, start, obs, used, W, setup, opt, opt.loss));

  // 2. Outliers at that solution (weights refreshed there).
  Camera cam = st.to_camera(start);
  W = whitening_matrices(cam, obs, opt.pixel_sigma_px);
  d.outlier_threshold_sigma = flag_outliers(cam, st.clock[0], obs, used, W, opt, &out);

  // 3. Plain least squares on the inliers, weights refreshed (iterated effective variance).
  if (opt.resolve_without_outliers) {
    for (std::size_t i = 0; i < n; ++i)
      if (out.outlier[i]) used[i] = 0, out.calibration.rejected.push_back(i);
    const int n_used = static_cast<int>(std::count(used.begin(), used.end(), 1));
    if (2 * n_used < setup.n_free)
      throw_calibration_error("bundle", "after rejecting " + std::to_string(n - n_used) +
                                            " outliers too few points remain (" + std::to_string(n_used) +
                                            ")");
    d.solves.push_back(solve(st, start, obs, used, W, setup, opt, RobustLoss::none));
    d.solves.back().rejected = n - static_cast<std::size_t>(n_used);
    cam = st.to_camera(start);
    W = whitening_matrices(cam, obs, opt.pixel_sigma_px);
    const std::vector<bool> dropped = out.outlier;
    d.outlier_threshold_sigma = flag_outliers(cam, st.clock[0], obs, used, W, opt, &out);
    out.outlier = dropped;  // the listed outliers are the ones dropped
  }
  for (const BundleSolve& s : d.solves) d.iterations += s.iterations;

  // 4. Covariance from the whitened Jacobian at the solution (w re-based to 0).
  const WhitenedSystem sys = whitened_system(st, start, obs, used, W, setup, opt);
  d.free = setup.free_parameters();
  const int p = static_cast<int>(d.free.size());
  d.chi2 = sys.r.squaredNorm();
  d.dof = static_cast<int>(sys.J.rows()) - p;
  d.variance_factor = d.dof > 0 ? d.chi2 / d.dof : std::numeric_limits<double>::quiet_NaN();
  const RankTestedInverse cov =
      estimate_covariance(sys.J, d.free, cam, bundle_scene_distance(cam, obs), max_speed, opt.rank_tolerance);

  CalibrationResult& cal = out.calibration;
  cal.camera_id = initial.id;
  cal.method = "bundle";
  cal.camera = cam;
  cal.clock_offset_s = st.clock[0];
  cal.parameters = d.free;
  out.warnings = rank_deficiency_warnings(cov.warnings, cov.named, d.free, initial.id);
  d.rank_deficient = cov.rank_deficient;
  if (!cov.rank_deficient) {
    // The sandwich under the PPK error model; N⁻¹ itself under the bundle's own weighting
    // (optim/bundle/correlated_ppk_covariance.hpp).
    out.covariance_unscaled =
        ppk_sandwich_covariance(cov.covariance, sys.J, cam, obs, used, W, opt.pixel_sigma_px, opt.ppk_error);
    out.covariance_scaled =
        out.covariance_unscaled * (std::isfinite(d.variance_factor) ? d.variance_factor : 1.0);
    cal.covariance = opt.scale_covariance ? out.covariance_scaled : out.covariance_unscaled;
    d.sigma_unscaled = out.covariance_unscaled.diagonal().cwiseSqrt();
    d.sigma_scaled = out.covariance_scaled.diagonal().cwiseSqrt();
  }
  cal.center_covariance_m2 = center_covariance(cal);
  cal.reprojection = reprojection_stats(out.residual_px, used);

  // 5. Diagnostics.
  d.covariance_scaled = opt.scale_covariance;
  d.pixel_sigma_px = opt.pixel_sigma_px;
  if (!is_bundle_weighting(opt.ppk_error)) {
    d.ppk_error_model = opt.ppk_error;
    d.gauss_markov_states = gauss_markov_chained(obs, used, opt.ppk_error);
  }
  if (setup.is_free(CameraParameter::clock_offset)) d.clock_offset_s = cal.clock_offset_s;
  for (std::size_t i = 0; i < n; ++i)
    if (out.outlier[i]) d.outliers.push_back(i);
  finish_bundle_result(max_speed, opt.correlation_warning, &out);
  return out;
}

void finish_bundle_result(double max_speed_mps, double correlation_warning, BundleResult* result) {
  CalibrationResult& cal = result->calibration;
  const BundleDetails& details = result->details;
  for (CalibrationWarning& warning : poorly_determined_warnings(cal, max_speed_mps, correlation_warning))
    result->warnings.push_back(std::move(warning));
  for (CalibrationWarning& warning : fit_warnings(details)) result->warnings.push_back(std::move(warning));
  for (CalibrationWarning& warning : result->warnings) warning.camera = cal.camera_id;
  cal.warnings = warning_texts(result->warnings);
  result->chi2 = details.chi2;
  result->dof = details.dof;
  result->variance_factor = details.variance_factor;
  result->rank_deficient = details.rank_deficient;
  result->iterations = details.iterations;
}

}  // namespace rangecal
