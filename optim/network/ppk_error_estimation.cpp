#include "optim/network/ppk_error_estimation.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "optim/network/gauss_markov_elimination.hpp"
#include "optim/network/network_covariance.hpp"
#include "optim/search/nelder_mead.hpp"

namespace rangecal {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// The mission's share of the normal equations that no model parameter changes, at the
/// linearisation: the images (and the poles' and cameras' priors) — every point's V, W and gradient
/// without its fix.
struct FixedPart {
  NetworkLayout layout;  ///< every PPK epoch in the chain (its gm_chain order, gm_state)
  std::vector<PointLinearisation> lin;
  std::vector<char> in_solve;             ///< the point is eliminated
  std::vector<char> fix;                  ///< its fix enters, weighed by the model
  std::vector<Eigen::Vector3d> residual;  ///< X − fix (m)
  MatrixXd U;
  VectorXd gradient;
  double chi2 = 0;
};

/// Keeps every stride-th state of the chain, stride = ⌈states / kEstimationEpochs⌉, and drops the
/// other epochs from `sel` (their fix and observations): the AR(1) is Markov, so the kept states'
/// prior, chained over the longer steps, is exactly their marginal.
void thin_chain(NetworkLayout* l, NetworkSelection* sel) {
  const std::size_t n = l->gm_chain.size();
  const std::size_t stride = (n + kEstimationEpochs - 1) / kEstimationEpochs;
  if (stride <= 1) return;
  std::vector<std::size_t> kept;
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t k = l->gm_chain[j];
    if (j % stride == 0) {
      l->gm_state[k] = static_cast<int>(kept.size());
      kept.push_back(k);
      continue;
    }
    l->gm_state[k] = -1;
    sel->prior[k] = 0;
    for (std::size_t i : l->by_point[k]) sel->observation[i] = 0;
  }
  l->gm_chain = std::move(kept);
}

FixedPart fixed_part(const NetworkLayout& any, const NetworkParameterBlocks& b, const NetworkSelection& sel) {
  PpkErrorModel chained;  // any correlated model: it only orders the chain
  chained.gm_sd_h_m = chained.gm_sd_v_m = 0.01, chained.tau_h_s = chained.tau_v_s = 30;
  FixedPart f;
  f.layout = make_network_layout(*any.cameras, *any.points, *any.observations, chained);
  f.layout.pixel_sigma_scale = any.pixel_sigma_scale;
  NetworkSelection images = sel;
  thin_chain(&f.layout, &images);
  const NetworkLayout& l = f.layout;
  refresh_single_view(l, b, &images);
  const std::size_t np = l.by_point.size();
  f.fix.assign(np, 0), f.in_solve.assign(np, 0), f.residual.assign(np, Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < np; ++k)
    if (l.gm_state[k] >= 0 && images.prior[k]) {
      f.fix[k] = 1, images.prior[k] = 0;
      f.residual[k] = Eigen::Map<const Eigen::Vector3d>(b.points[k].data()) - (*l.points)[k].prior_enu;
    }
  const int n = l.n_camera_parameters;
  f.U = MatrixXd::Zero(n, n), f.gradient = VectorXd::Zero(n);
  int rows = 0;
  f.lin.resize(np);
  for (std::size_t k = 0; k < np; ++k) {
    f.lin[k] = linearise_point(l, b, images, k, &f.U, &f.chi2, &rows);
    for (const auto& [c, g] : f.lin[k].grad_camera) f.gradient.segment(l.offset[c], g.size()) += g;
    f.in_solve[k] = f.fix[k] || !f.lin[k].V.isZero(0);
  }
  add_camera_priors(l, b, &f.U, &f.chi2, &rows, &f.gradient);
  return f;
}

/// The chain's AR(1) prior under `m` into the states' system; returns log|P| (P its covariance).
double chain_prior(const NetworkLayout& l, const PpkErrorModel& m, GaussMarkovSystem* gm) {
  double log_det = 0;
  for (std::size_t j = 0; j < l.gm_chain.size(); ++j) {
    Eigen::Vector3d phi = Eigen::Vector3d::Zero();
    if (j > 0)
      phi = gauss_markov_transition(
          m, (*l.points)[l.gm_chain[j]].time_s - (*l.points)[l.gm_chain[j - 1]].time_s);
    const Eigen::Vector3d w = gauss_markov_weight(m, j > 0 ? &phi : nullptr);
    const Eigen::Vector3d w2 = w.cwiseProduct(w);
    log_det -= 2 * w.array().log().sum();
    gm->diagonal[j].diagonal() += w2;
    if (j > 0) {
      gm->diagonal[j - 1].diagonal() += w2.cwiseProduct(phi).cwiseProduct(phi);
      gm->below[j] = -w2.cwiseProduct(phi);
    }
  }
  return log_det;
}

/// −2ℓ_R (ppk_error_estimation.hpp) of `m`; with `chain` false the white model S·Σ_pos·S alone.
double deviance(const FixedPart& f, const PpkErrorModel& m, bool chain) {
  const NetworkLayout& l = f.layout;
  const std::size_t states = chain ? l.gm_chain.size() : 0;
  MatrixXd S = f.U;
  VectorXd gc = f.gradient;
  double chi2 = f.chi2, log_det = 0, decrease = 0;
  GaussMarkovSystem gm;
  gm.diagonal.assign(states, Eigen::Matrix3d::Zero());
  gm.below.assign(states, Eigen::Vector3d::Zero());
  gm.B = MatrixXd::Zero(3 * static_cast<Eigen::Index>(states), l.n_camera_parameters);
  gm.gradient = VectorXd::Zero(3 * static_cast<Eigen::Index>(states));
  if (chain) log_det += chain_prior(l, m, &gm);
  const Eigen::Matrix3d scale = m.white_scale().asDiagonal();
  for (std::size_t k = 0; k < f.lin.size(); ++k) {
    if (!f.in_solve[k]) continue;
    const PointLinearisation& lin = f.lin[k];
    Eigen::Matrix3d V = lin.V, P = Eigen::Matrix3d::Zero();
    Eigen::Vector3d bX = lin.grad_point, Pe = Eigen::Vector3d::Zero();
    if (f.fix[k]) {  // the fix X + g + w, Cov(w) = S·Σ_pos·S (ppk_error_model.hpp)
      const Eigen::Matrix3d white = scale * (*l.points)[k].prior_cov * scale;
      P = white.inverse(), Pe = P * f.residual[k];
      log_det += std::log(white.determinant());
      V += P, bX += Pe, chi2 += f.residual[k].dot(Pe);
    }
    const Eigen::LLT<Eigen::Matrix3d> llt(V);
    if (llt.info() != Eigen::Success) return kInfinity;
    log_det += 2 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
    const Eigen::Matrix3d Vinv = llt.solve(Eigen::Matrix3d::Identity());
    const Eigen::Vector3d VbX = Vinv * bX;
    decrease += bX.dot(VbX);
    for (const auto& [c1, W1] : lin.W) {
      gc.segment(l.offset[c1], W1.rows()) -= W1 * VbX;
      for (const auto& [c2, W2] : lin.W)
        S.block(l.offset[c1], l.offset[c2], W1.rows(), W2.rows()).noalias() -= W1 * Vinv * W2.transpose();
    }
    if (states == 0 || !f.fix[k]) continue;
    const Eigen::Index j = 3 * static_cast<Eigen::Index>(l.gm_state[k]);
    const Eigen::Matrix3d PV = P * Vinv;
    gm.diagonal[static_cast<std::size_t>(l.gm_state[k])] += P - PV * P;
    gm.gradient.segment<3>(j) += Pe - PV * bX;
    for (const auto& [c, W] : lin.W) gm.B.block(j, l.offset[c], 3, W.rows()).noalias() -= PV * W.transpose();
  }
  if (states > 0) {
    VectorXd solved = gm.gradient;
    double log_g = 0;
    try {
      eliminate_gauss_markov(&gm, &S, &solved, &gc, &log_g);
    } catch (const std::exception&) {
      return kInfinity;
    }
    log_det += log_g, decrease += gm.gradient.dot(solved);
  }
  const VectorXd d = S.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::LDLT<MatrixXd> ldlt(d.asDiagonal() * S * d.asDiagonal());
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all()) return kInfinity;
  log_det += ldlt.vectorD().array().log().sum() - 2 * d.array().log().sum();
  decrease += gc.dot(d.asDiagonal() * ldlt.solve(d.asDiagonal() * gc));
  return log_det + chi2 - decrease;
}

/// The model's six parameters in log form: s_h, s_v, σ_h, σ_v, τ_h, τ_v.
using LogParameters = Eigen::Matrix<double, 6, 1>;
const std::array<double, 6> kLow = {0.01, 0.01, 1e-4, 1e-4, 0.1, 0.1};
const std::array<double, 6> kHigh = {10, 10, 1, 1, 1e5, 1e5};

PpkErrorModel model_of(const LogParameters& x) {
  PpkErrorModel m;
  double* fields[6] = {&m.white_scale_h, &m.white_scale_v, &m.gm_sd_h_m,
                       &m.gm_sd_v_m,     &m.tau_h_s,       &m.tau_v_s};
  for (int i = 0; i < 6; ++i) *fields[i] = std::exp(x[i]);
  return m;
}

/// The model's deviance with the parameters outside their ranges pulled back and penalised, so that
/// the simplex stays in the physical box.
double bounded_deviance(const FixedPart& f, LogParameters x, bool chain) {
  double penalty = 0;
  for (int i = 0; i < 6; ++i) {
    const double lo = std::log(kLow[static_cast<std::size_t>(i)]),
                 hi = std::log(kHigh[static_cast<std::size_t>(i)]);
    const double clamped = std::clamp(x[i], lo, hi);
    penalty += 1e3 * (x[i] - clamped) * (x[i] - clamped);
    x[i] = clamped;
  }
  return deviance(f, model_of(x), chain) + penalty;
}

/// Minimises over the parameters `free` lists (the others held at `x`); returns the minimiser.
struct Fit {
  LogParameters x;
  double value = kInfinity;
  int evaluations = 0;
};
Fit fit(const FixedPart& f, const LogParameters& x, const std::vector<int>& free, bool chain) {
  const Eigen::Index n = static_cast<Eigen::Index>(free.size());
  auto full = [&](const VectorXd& y) {
    LogParameters z = x;
    for (Eigen::Index i = 0; i < n; ++i) z[free[static_cast<std::size_t>(i)]] = y[i];
    return z;
  };
  VectorXd y0(n);
  for (Eigen::Index i = 0; i < n; ++i) y0[i] = x[free[static_cast<std::size_t>(i)]];
  Fit out;
  // Two passes: a restart from the first minimum guards against a collapsed simplex.
  for (int pass = 0; pass < 2; ++pass) {
    const NelderMeadResult r =
        nelder_mead([&](const VectorXd& y) { return bounded_deviance(f, full(y), chain); }, y0,
                    VectorXd::Constant(n, pass == 0 ? 0.5 : 0.2), 1e-4, 400 * static_cast<int>(n));
    out.evaluations += r.evaluations;
    y0 = r.x, out.x = full(r.x), out.value = r.value;
  }
  return out;
}

/// 1σ of the free parameters from the deviance's Hessian in log form (Cov(log θ) = 2·H⁻¹,
/// central differences); NaN where the Hessian is not positive definite.
LogParameters log_sd(const FixedPart& f, const Fit& best, const std::vector<int>& free, bool chain,
                     int* evaluations) {
  const int n = static_cast<int>(free.size());
  constexpr double h = 0.05;
  auto at = [&](int i, double di, int j, double dj) {
    LogParameters z = best.x;
    z[free[static_cast<std::size_t>(i)]] += di;
    if (j >= 0) z[free[static_cast<std::size_t>(j)]] += dj;
    ++*evaluations;
    return bounded_deviance(f, z, chain);
  };
  MatrixXd H(n, n);
  for (int i = 0; i < n; ++i) {
    H(i, i) = (at(i, h, -1, 0) - 2 * best.value + at(i, -h, -1, 0)) / (h * h);
    for (int j = 0; j < i; ++j)
      H(i, j) = H(j, i) =
          (at(i, h, j, h) - at(i, h, j, -h) - at(i, -h, j, h) + at(i, -h, j, -h)) / (4 * h * h);
  }
  LogParameters sd = LogParameters::Constant(std::numeric_limits<double>::quiet_NaN());
  const Eigen::LLT<MatrixXd> llt(H);
  if (llt.info() != Eigen::Success) return sd;
  const MatrixXd cov = 2 * llt.solve(MatrixXd::Identity(n, n));
  for (int i = 0; i < n; ++i) sd[free[static_cast<std::size_t>(i)]] = std::sqrt(cov(i, i));
  return sd;
}

/// σ of θ = exp(x) from σ of x (delta method), into the fields of a model.
PpkErrorModel sd_of(const LogParameters& x, const LogParameters& sd) {
  PpkErrorModel m = model_of(x), s;
  const double values[6] = {m.white_scale_h, m.white_scale_v, m.gm_sd_h_m, m.gm_sd_v_m, m.tau_h_s, m.tau_v_s};
  double* fields[6] = {&s.white_scale_h, &s.white_scale_v, &s.gm_sd_h_m,
                       &s.gm_sd_v_m,     &s.tau_h_s,       &s.tau_v_s};
  for (int i = 0; i < 6; ++i) *fields[i] = values[i] * sd[i];
  return s;
}

/// The .pos sd per axis group (rms of E, N and of U over the chained fixes; m).
Eigen::Vector2d reported_sd(const FixedPart& f) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int n = 0;
  for (std::size_t k = 0; k < f.fix.size(); ++k)
    if (f.fix[k]) {
      const Eigen::Matrix3d& c = (*f.layout.points)[k].prior_cov;
      sum += Eigen::Vector2d(0.5 * (c(0, 0) + c(1, 1)), c(2, 2)), ++n;
    }
  return n > 0 ? Eigen::Vector2d((sum / n).cwiseSqrt()) : Eigen::Vector2d(0.01, 0.01);
}

/// The start of the simplex: a shared τ from a grid, the variance split ¼ white, ¾ Gauss–Markov.
LogParameters starting_point(const FixedPart& f, int* evaluations) {
  const Eigen::Vector2d sd = reported_sd(f);
  LogParameters x;
  x << std::log(0.5), std::log(0.5), std::log(0.85 * sd[0]), std::log(0.85 * sd[1]), 0, 0;
  double best = kInfinity, best_tau = 30;
  for (double tau : {1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0}) {
    x[4] = x[5] = std::log(tau);
    ++*evaluations;
    const double v = bounded_deviance(f, x, true);
    if (v < best) best = v, best_tau = tau;
  }
  x[4] = x[5] = std::log(best_tau);
  return x;
}

}  // namespace

double restricted_deviance(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                           const NetworkSelection& selection, const PpkErrorModel& model) {
  return deviance(fixed_part(layout, blocks, selection), model, model.correlated());
}

PpkErrorEstimate estimate_ppk_error_model(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                                          const NetworkSelection& selection) {
  PpkErrorEstimate out;
  const FixedPart f = fixed_part(layout, blocks, selection);
  std::vector<double> t;
  for (std::size_t k : f.layout.gm_chain)
    if (f.fix[k]) t.push_back((*f.layout.points)[k].time_s);
  if (t.size() < 2) return out;
  out.record_s = t.back() - t.front();

  // The white model (scales alone) and the Gauss–Markov model, each at its maximum.
  LogParameters white_x = LogParameters::Zero();
  white_x[2] = white_x[3] = std::log(kLow[2]), white_x[4] = white_x[5] = std::log(1.0);
  const Fit white = fit(f, white_x, {0, 1}, false);
  const Fit gm = fit(f, starting_point(f, &out.evaluations), {0, 1, 2, 3, 4, 5}, true);
  out.evaluations += white.evaluations + gm.evaluations;
  out.likelihood_ratio = white.value - gm.value;
  if (!(out.likelihood_ratio >= kWhiteLikelihoodRatio)) {
    out.white = true;
    out.model = model_of(white.x);
    out.model.gm_sd_h_m = out.model.gm_sd_v_m = out.model.tau_h_s = out.model.tau_v_s = 0;
    out.sd = sd_of(white.x, log_sd(f, white, {0, 1}, false, &out.evaluations));
    out.sd.gm_sd_h_m = out.sd.gm_sd_v_m = out.sd.tau_h_s = out.sd.tau_v_s =
        std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  // A record shorter than kRecordPerTau·τ̂ pins the increments' rate σ_g²/τ, not σ_g and τ apart
  // (ppk_error_estimation.hpp): hold σ_g at the .pos sd and estimate τ (and s) with it.
  Fit best = gm;
  std::vector<int> free = {0, 1, 4, 5};
  out.gm_sd_held_h = out.record_s < kRecordPerTau * std::exp(gm.x[4]);
  out.gm_sd_held_v = out.record_s < kRecordPerTau * std::exp(gm.x[5]);
  if (!out.gm_sd_held_h) free.push_back(2);
  if (!out.gm_sd_held_v) free.push_back(3);
  if (out.gm_sd_held_h || out.gm_sd_held_v) {
    const Eigen::Vector2d pos_sd = reported_sd(f);
    LogParameters x = gm.x;
    if (out.gm_sd_held_h) x[2] = std::log(pos_sd[0]), x[4] += 2 * (x[2] - gm.x[2]);
    if (out.gm_sd_held_v) x[3] = std::log(pos_sd[1]), x[5] += 2 * (x[3] - gm.x[3]);
    best = fit(f, x, free, true);  // started on the ridge: τ scaled with σ_g² (same rate)
    out.evaluations += best.evaluations;
  }
  out.model = model_of(best.x);
  out.sd = sd_of(best.x, log_sd(f, best, free, true, &out.evaluations));
  return out;
}

}  // namespace rangecal
