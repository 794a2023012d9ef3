#include "optim/bundle/correlated_ppk_covariance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "optim/bundle/bundle_covariance.hpp"
#include "optim/bundle/bundle_parameters.hpp"
#include "optim/bundle/whitening.hpp"

namespace rangecal {

using Eigen::Matrix2d;
using Eigen::Matrix3d;
using Eigen::MatrixXd;

bool is_bundle_weighting(const PpkErrorModel& m) {
  return m.white_scale_h == 1 && m.white_scale_v == 1 && !m.correlated();
}

MatrixXd exponential_kernel_sum(const MatrixXd& H, const std::vector<double>& t, double tau) {
  const Eigen::Index p = H.rows();
  MatrixXd X = MatrixXd::Zero(p, p), D = MatrixXd::Zero(p, p);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(p);
  for (Eigen::Index k = 0; k < H.cols(); ++k) {
    const std::size_t ks = static_cast<std::size_t>(k);
    const double phi = k == 0 ? 0.0 : gauss_markov_transition(t[ks] - t[ks - 1], tau);
    f = phi * f + H.col(k);  // Σ_{j≤k} exp(−(t_k − t_j)/τ)·h_j
    X.noalias() += H.col(k) * f.transpose();
    D.noalias() += H.col(k) * H.col(k).transpose();
  }
  return X + X.transpose() - D;
}

namespace {

/// A PPK fix with a time: white-scaled, and on the chain when the model has a GM part.
bool ppk_fix(const BundleObservation& o) {
  return std::isfinite(o.time_s);
}

}  // namespace

int gauss_markov_chained(const std::vector<BundleObservation>& obs, const std::vector<char>& used,
                         const PpkErrorModel& model) {
  if (!model.correlated()) return 0;
  int n = 0;
  for (std::size_t i = 0; i < obs.size(); ++i) n += used[i] && ppk_fix(obs[i]) ? 1 : 0;
  return n;
}

MatrixXd correlated_ppk_meat(const MatrixXd& J, const Camera& cam, const std::vector<BundleObservation>& obs,
                             const std::vector<char>& used, const std::vector<Matrix2d>& W,
                             double default_sigma_px, const PpkErrorModel& model) {
  const Eigen::Index p = J.cols();
  const Matrix3d S = model.white_scale().asDiagonal();
  const bool chain = model.correlated();
  MatrixXd M = MatrixXd::Zero(p, p);
  std::vector<std::size_t> chained;             // observation index, in row order
  std::vector<Eigen::Matrix<double, -1, 3>> G;  // J_iᵀ·W_i·J_X,i of each chained observation
  Eigen::Index row = 0;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    if (!used[i]) continue;
    const BundleObservation& o = obs[i];
    const double s = o.pixel_sigma_px > 0 ? o.pixel_sigma_px : default_sigma_px;
    const Eigen::Matrix<double, 2, 3> B = W[i] * pixel_jacobian_wrt_world(cam, o.world);
    const Matrix3d white = ppk_fix(o) ? Matrix3d(S * o.world_cov * S) : o.world_cov;
    const Matrix2d C = s * s * W[i] * W[i].transpose() + B * white * B.transpose();
    const auto Ji = J.middleRows(row, 2);
    M.noalias() += Ji.transpose() * C * Ji;
    if (chain && ppk_fix(o)) chained.push_back(i), G.push_back(Ji.transpose() * B);
    row += 2;
  }
  const auto prior = J.bottomRows(J.rows() - row);  // whitened priors: unit variance, independent
  M.noalias() += prior.transpose() * prior;
  if (chained.empty()) return M;
  std::vector<std::size_t> order(chained.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return obs[chained[a]].time_s < obs[chained[b]].time_s;
  });
  std::vector<double> t;
  for (std::size_t k : order) t.push_back(obs[chained[k]].time_s);
  const Eigen::Vector3d sd = model.gm_sd(), tau = model.tau();
  MatrixXd H(p, static_cast<Eigen::Index>(order.size()));
  for (int a = 0; a < 3; ++a) {
    for (std::size_t k = 0; k < order.size(); ++k) H.col(static_cast<Eigen::Index>(k)) = G[order[k]].col(a);
    M += sd[a] * sd[a] * exponential_kernel_sum(H, t, tau[a]);
  }
  return M;
}

BundleCovariance bundle_covariance_under(const PpkErrorModel& model,
                                         const std::vector<BundleObservation>& obs, const BundleOptions& opt,
                                         const CalibrationResult& solution) {
  const BundleSetup setup = bundle_setup(opt);
  const Camera& cam = solution.camera;
  const BundleParameterBlocks st = BundleParameterBlocks::from_camera(cam, solution.clock_offset_s);
  std::vector<char> used(obs.size(), 1);
  for (std::size_t i : solution.rejected)
    if (i < used.size()) used[i] = 0;
  const std::vector<Matrix2d> W = whitening_matrices(cam, obs, opt.pixel_sigma_px);
  const WhitenedSystem sys = whitened_system(st, cam, obs, used, W, setup, opt);
  BundleCovariance out;
  out.free = setup.free_parameters();
  out.chi2 = sys.r.squaredNorm();
  out.dof = static_cast<int>(sys.J.rows()) - static_cast<int>(out.free.size());
  out.variance_factor = out.dof > 0 ? out.chi2 / out.dof : std::numeric_limits<double>::quiet_NaN();
  const RankTestedInverse cov = estimate_covariance(sys.J, out.free, cam, bundle_scene_distance(cam, obs),
                                                    bundle_max_speed(obs), opt.rank_tolerance);
  out.rank_deficient = cov.rank_deficient;
  out.gauss_markov_states = gauss_markov_chained(obs, used, model);
  if (cov.rank_deficient) return out;
  out.covariance_unscaled =
      ppk_sandwich_covariance(cov.covariance, sys.J, cam, obs, used, W, opt.pixel_sigma_px, model);
  out.covariance_scaled =
      out.covariance_unscaled * (std::isfinite(out.variance_factor) ? out.variance_factor : 1.0);
  return out;
}

MatrixXd ppk_sandwich_covariance(const MatrixXd& Ninv, const MatrixXd& J, const Camera& cam,
                                 const std::vector<BundleObservation>& obs, const std::vector<char>& used,
                                 const std::vector<Matrix2d>& W, double default_sigma_px,
                                 const PpkErrorModel& model) {
  if (is_bundle_weighting(model)) return Ninv;
  const MatrixXd C = Ninv * correlated_ppk_meat(J, cam, obs, used, W, default_sigma_px, model) * Ninv;
  return 0.5 * (C + C.transpose());
}

}  // namespace rangecal
