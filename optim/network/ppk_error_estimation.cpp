#include "optim/network/ppk_error_estimation.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "config/number_format.hpp"
#include "gnss/track/ppk_error_model.hpp"
#include "gnss/track/ppk_error_model_json.hpp"
#include "optim/network/restricted_likelihood.hpp"

namespace rangecal {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

/// The box of the PPK parameters (white scales, Gauss–Markov sd in m, τ in s), then of every image
/// scale (ppk_error_estimation.hpp).
const std::array<double, kPpkParameters + 1> kLow = {0.01, 0.01, 1e-4, 1e-4, 0.1, 0.1, kLowestImageScale};
/// The upper bounds are those a model read from JSON may take (gnss/track/ppk_error_model_json.hpp).
const std::array<double, kPpkParameters + 1> kHigh = {
    kMaxWhiteScale,      kMaxWhiteScale,      kMaxGaussMarkovSdM, kMaxGaussMarkovSdM,
    kMaxGaussMarkovTauS, kMaxGaussMarkovTauS, kHighestImageScale};
/// Newton's iterations per fit at most, the largest step (log units: a factor e^1.5 at once), and
/// the decrease of D (predicted, or made by a step) below which a fit has converged: 1 % of the
/// ΔD a 1σ change of a parameter makes (the estimate is then within ~0.1σ of the maximum).
constexpr int kMaxIterations = 40;
/// Within this of a bound (log units: 0.01 %) a parameter is on it.
constexpr double kOnBound = 1e-4;
constexpr double kMaxStep = 1.5;
constexpr double kConverged = 1e-2;

double low(int i) {
  return std::log(kLow[static_cast<std::size_t>(std::min(i, kPpkParameters))]);
}
double high(int i) {
  return std::log(kHigh[static_cast<std::size_t>(std::min(i, kPpkParameters))]);
}

LogParameters in_box(LogParameters x) {
  for (int i = 0; i < static_cast<int>(x.size()); ++i) x[i] = std::clamp(x[i], low(i), high(i));
  return x;
}

/// The likelihood of one model family (white, or white + Gauss–Markov) on the mission, counting the
/// points it is factored at (its evaluations).
struct Likelihood {
  const RemlMission& mission;
  bool chain;
  int* evaluations;
  /// D at x, factored into `factors`.
  double deviance(const LogParameters& x, RemlFactors* factors) const {
    ++*evaluations;
    factor_restricted_likelihood(mission, x, chain, factors);
    return factors->deviance;
  }
  RemlEvaluation derivatives(const RemlFactors& factors) const {
    return restricted_likelihood_derivatives(mission, factors);
  }
};

/// A point of the search with the normal equations factored there.
struct Point {
  LogParameters x;
  RemlFactors factors;
};

Point point_at(const Likelihood& likelihood, const LogParameters& x) {
  Point p{in_box(x), {}};
  likelihood.deviance(p.x, &p.factors);
  return p;
}

/// A fit: the minimiser and the evaluation there (with derivatives).
struct Fit {
  LogParameters x;
  RemlEvaluation at;
};

/// The free parameters a step may move: those not held at a bound by their gradient.
std::vector<int> moving_parameters(const LogParameters& x, const LogParameters& gradient,
                                   const std::vector<int>& free) {
  std::vector<int> moving;
  for (int i : free)
    if (!(x[i] <= low(i) + 1e-12 && gradient[i] > 0) && !(x[i] >= high(i) - 1e-12 && gradient[i] < 0))
      moving.push_back(i);
  return moving;
}

/// The damped Newton step −(H + λ·diag(H))⁻¹·g, H = 2·AI (restricted_likelihood.hpp), at most
/// kMaxStep long; zero where the damped matrix is not positive definite.
VectorXd damped_step(const MatrixXd& H, const VectorXd& g, double lambda) {
  MatrixXd A = H;
  A.diagonal() += lambda * H.diagonal().cwiseAbs() +
                  VectorXd::Constant(g.size(), 1e-9 * std::max(1e-300, H.diagonal().cwiseAbs().maxCoeff()));
  const Eigen::LLT<MatrixXd> llt(A);
  if (llt.info() != Eigen::Success) return VectorXd::Zero(g.size());
  VectorXd step = -llt.solve(g);
  const double longest = step.cwiseAbs().maxCoeff();
  if (longest > kMaxStep) step *= kMaxStep / longest;
  return step;
}

/// Levenberg–Marquardt's damping after a step whose fall was `gain` times the predicted one: more
/// where the quadratic model predicted poorly, less (down to none) where it predicted well.
double next_damping(double lambda, double gain) {
  if (gain < 0.25) return std::max(1e-2, 4 * lambda);
  if (gain > 0.75) return lambda < 1e-3 ? 0 : lambda / 4;
  return lambda;
}

/// Minimises D over the parameters `free` (the others held at `x`) by Levenberg–Marquardt on
/// Newton's step with the average information as the curvature (Fisher scoring's safeguard where
/// the start is far from the maximum and AI is a poor curvature), each step kept in the box.
Fit fit(const Likelihood& likelihood, Point start, const std::vector<int>& free) {
  LogParameters x = start.x;
  RemlFactors here_factors = std::move(start.factors), tried;
  RemlEvaluation here = likelihood.derivatives(here_factors);
  double lambda = 0;
  for (int iteration = 0; iteration < kMaxIterations && std::isfinite(here.deviance); ++iteration) {
    const std::vector<int> moving = moving_parameters(x, here.gradient, free);
    const auto n = static_cast<Eigen::Index>(moving.size());
    if (n == 0) break;
    MatrixXd H(n, n);
    VectorXd g(n);
    for (Eigen::Index a = 0; a < n; ++a) {
      g[a] = here.gradient[moving[static_cast<std::size_t>(a)]];
      for (Eigen::Index b = 0; b < n; ++b)
        H(a, b) =
            2 * here.information(moving[static_cast<std::size_t>(a)], moving[static_cast<std::size_t>(b)]);
    }
    bool moved = false, converged = false;
    for (int attempt = 0; attempt < 12 && !moved && !converged; ++attempt) {
      const VectorXd step = damped_step(H, g, lambda);
      const double predicted = -g.dot(step) - 0.5 * step.dot(H * step);
      if (predicted < kConverged) {
        converged = lambda == 0 || step.isZero(0);
        lambda = 0;  // the undamped step has the last word on convergence
        continue;
      }
      LogParameters y = x;
      for (Eigen::Index a = 0; a < n; ++a) y[moving[static_cast<std::size_t>(a)]] += step[a];
      y = in_box(y);
      // D alone at the trial point; the derivatives only where the step is taken, from its factors.
      const double actual = here.deviance - likelihood.deviance(y, &tried);
      if (!(actual > 0)) {
        lambda = std::max(1e-2, 4 * lambda);
        continue;
      }
      lambda = next_damping(lambda, actual / predicted);
      converged = actual < kConverged;
      std::swap(here_factors, tried);
      x = y, here = likelihood.derivatives(here_factors), moved = true;
    }
    if (!moved || converged) break;
  }
  return {x, here};
}

/// 1σ of the free parameters in log form, Cov(log θ) = AI⁻¹ over them; NaN where AI is not
/// positive definite.
LogParameters log_sd(const Fit& best, const std::vector<int>& free) {
  const auto n = static_cast<Eigen::Index>(free.size());
  MatrixXd ai(n, n);
  for (Eigen::Index a = 0; a < n; ++a)
    for (Eigen::Index b = 0; b < n; ++b)
      ai(a, b) = best.at.information(free[static_cast<std::size_t>(a)], free[static_cast<std::size_t>(b)]);
  LogParameters sd = LogParameters::Constant(best.x.size(), std::numeric_limits<double>::quiet_NaN());
  const Eigen::LLT<MatrixXd> llt(ai);
  if (llt.info() != Eigen::Success) return sd;
  const MatrixXd cov = llt.solve(MatrixXd::Identity(n, n));
  for (Eigen::Index a = 0; a < n; ++a) sd[free[static_cast<std::size_t>(a)]] = std::sqrt(cov(a, a));
  return sd;
}

/// σ of θ = exp(x) from σ of x (delta method), into the fields of a model.
PpkErrorModel sd_of(const LogParameters& x, const LogParameters& sd) {
  PpkErrorModel m = model_of(x), s;
  const double values[6] = {m.white_scale_h, m.white_scale_v, m.gm_sd_h_m, m.gm_sd_v_m, m.tau_h_s, m.tau_v_s};
  double* fields[6] = {&s.white_scale_h, &s.white_scale_v, &s.gm_sd_h_m,
                       &s.gm_sd_v_m,     &s.tau_h_s,       &s.tau_v_s};
  for (int i = 0; i < kPpkParameters; ++i) *fields[i] = values[i] * sd[i];
  return s;
}

/// A parameter's name in messages (the order of LogParameters).
std::string parameter_label(int i) {
  static const char* const kPpk[kPpkParameters] = {
      "horizontal white scale",   "vertical white scale", "horizontal Gauss–Markov sd",
      "vertical Gauss–Markov sd", "horizontal τ",         "vertical τ"};
  return i < kPpkParameters ? kPpk[i] : "camera " + std::to_string(i - kPpkParameters) + " image scale";
}

/// True when parameter i's lower bound is a variance component at zero — a white scale or a
/// Gauss–Markov sd: an estimate there says that part of the error is negligible, which REML may
/// rightly find (Harville 1977), not that the mission cannot tell.
bool zero_at_low_bound(int i) {
  return i < 4;
}

/// The free parameters of x on a bound of their box that the mission does not determine, named
/// (parameter_label) with their value: any bound of τ and of an image scale, the upper bound of a
/// white scale or sd (a variance component at zero, zero_at_low_bound, is not among them).
std::vector<std::string> on_bound(const LogParameters& x, const std::vector<int>& free) {
  std::vector<std::string> out;
  for (int i : free)
    if ((x[i] <= low(i) + kOnBound && !zero_at_low_bound(i)) || x[i] >= high(i) - kOnBound)
      out.push_back(parameter_label(i) + " on its bound (" + format_number("%g", std::exp(x[i])) + ")");
  return out;
}

/// The Gauss–Markov fit's PPK parameters that the mission does not determine (on_bound).
std::vector<std::string> unidentified(const LogParameters& x, const std::vector<int>& free) {
  std::vector<int> ppk;
  for (int i : free)
    if (i < kPpkParameters) ppk.push_back(i);
  return on_bound(x, ppk);
}

/// `fit` again with every image scale that went to its lower bound held at 1 (the stated σ), removed
/// from `images` and marked in `held`: its camera's centroids are hidden by the fixes' own error (a
/// centroid far sharper than a fix projects), the likelihood would take their σ to zero, and the
/// stated σ is the better value to weigh them by (docs/optimisation.md "Image variance components").
/// `ppk` are the fit's free PPK parameters.
Fit hold_hidden_images(const Likelihood& likelihood, Fit fit_so_far, const std::vector<int>& ppk,
                       std::vector<int>* images, std::vector<char>* held) {
  for (std::size_t round = 0; round < held->size(); ++round) {
    LogParameters x = fit_so_far.x;
    bool any = false;
    for (auto it = images->begin(); it != images->end();) {
      if (x[*it] > low(*it) + kOnBound) {
        ++it;
        continue;
      }
      x[*it] = 0;
      (*held)[static_cast<std::size_t>(*it - kPpkParameters)] = 1;
      it = images->erase(it), any = true;
    }
    if (!any) break;
    std::vector<int> free = ppk;
    free.insert(free.end(), images->begin(), images->end());
    fit_so_far = fit(likelihood, point_at(likelihood, x), free);
  }
  return fit_so_far;
}

/// The image scales of x and their 1σ (delta method) into the estimate.
void image_scales_into(const LogParameters& x, const LogParameters& sd, PpkErrorEstimate* out) {
  const auto cameras = static_cast<std::size_t>(x.size() - kPpkParameters);
  out->image_scale.assign(cameras, 1), out->image_scale_sd.assign(cameras, 0);
  for (std::size_t c = 0; c < cameras; ++c) {
    const Eigen::Index i = kPpkParameters + static_cast<Eigen::Index>(c);
    out->image_scale[c] = std::exp(x[i]);
    out->image_scale_sd[c] = out->image_scale[c] * sd[i];
  }
}

/// The image scales' start: each camera's lamp centroids' rms whitened residual at the
/// linearisation (the robust solution); the cameras without one are not estimated (held at 1).
std::vector<int> start_image_scales(const RemlMission& f, LogParameters* x) {
  std::vector<int> free;
  for (std::size_t c = 0; c < f.cameras(); ++c) {
    if (f.image_rows[c] == 0) continue;
    const int i = kPpkParameters + static_cast<int>(c);
    (*x)[i] =
        std::clamp(0.5 * std::log(std::max(f.image_chi2[c], 1e-300) / f.image_rows[c]), low(i), high(i));
    free.push_back(i);
  }
  return free;
}

/// The .pos sd per axis group (rms of E, N and of U over the chained fixes; m).
Eigen::Vector2d reported_sd(const RemlMission& f) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int n = 0;
  for (std::size_t k = 0; k < f.fix.size(); ++k)
    if (f.fix[k]) {
      const Eigen::Matrix3d& c = (*f.layout.points)[k].prior_cov;
      sum += Eigen::Vector2d(0.5 * (c(0, 0) + c(1, 1)), c(2, 2)), ++n;
    }
  return n > 0 ? Eigen::Vector2d((sum / n).cwiseSqrt()) : Eigen::Vector2d(0.01, 0.01);
}

/// Moments of the white fit's corrections per axis group (h: E and N pooled, v: U): their mean square
/// c₀ and half the mean square of successive differences d₁, with the Δt of each difference (s).
struct CorrectionMoments {
  Eigen::Vector2d c0 = Eigen::Vector2d::Zero(), d1 = Eigen::Vector2d::Zero();
  std::vector<double> dt;
};

CorrectionMoments correction_moments(const std::vector<Eigen::Vector3d>& e, const std::vector<double>& t) {
  CorrectionMoments m;
  const double n = static_cast<double>(e.size());
  for (const Eigen::Vector3d& v : e)
    m.c0 += Eigen::Vector2d(0.5 * v.head<2>().squaredNorm(), v[2] * v[2]) / n;
  for (std::size_t j = 1; j < e.size(); ++j) {
    const Eigen::Vector3d d = e[j] - e[j - 1];
    m.d1 += Eigen::Vector2d(0.25 * d.head<2>().squaredNorm(), 0.5 * d[2] * d[2]) / (n - 1);
    m.dt.push_back(t[j] - t[j - 1]);
  }
  return m;
}

/// The split of the corrections' variance between white noise and a Gauss–Markov process of time
/// constant τ that their moments give: c₀ = σ_w² + σ_g², d₁ = σ_w² + σ_g²·(1 − φ̄), φ̄ the mean
/// exp(−Δt/τ) between successive fixes; each part kept ≥ 5 % of c₀. Returns (log s_h, log s_v,
/// log σ_h, log σ_v) for the .pos sd `sd`.
Eigen::Vector4d moment_split(const CorrectionMoments& m, double tau, const Eigen::Vector2d& sd) {
  double phi = 0;
  for (double dt : m.dt) phi += gauss_markov_transition(dt, tau) / static_cast<double>(m.dt.size());
  Eigen::Vector4d x;
  for (int a = 0; a < 2; ++a) {
    const double c0 = std::max(m.c0[a], 1e-12);
    const double gm = std::clamp((m.c0[a] - m.d1[a]) / std::max(phi, 1e-6), 0.05 * c0, 0.95 * c0);
    x[a] = 0.5 * std::log((c0 - gm) / (sd[a] * sd[a]));
    x[2 + a] = 0.5 * std::log(gm);
  }
  return x;
}

/// The Gauss–Markov fit's start: a shared τ from a grid, the variance split at each τ as the white
/// fit's corrections give it (moment_split); or, where D is lower there, the white fit's scales with a
/// small Gauss–Markov part (¼ of the .pos sd) at that τ — the start near the white model the family
/// nests.
Point starting_point(const Likelihood& likelihood, const Fit& white, const std::vector<double>& t) {
  const Eigen::Vector2d sd = reported_sd(likelihood.mission);
  const CorrectionMoments moments = correction_moments(white.at.corrections, t);
  Point best, tried;
  bool first = true;
  for (double tau : {1.0, 10.0, 100.0, 1000.0}) {
    const Eigen::Vector4d split = moment_split(moments, tau, sd);
    tried.x = white.x;
    tried.x.head<kPpkParameters>() << split[0], split[1], split[2], split[3], std::log(tau), std::log(tau);
    tried.x = in_box(tried.x);
    if (likelihood.deviance(tried.x, &tried.factors) < best.factors.deviance || first) std::swap(best, tried);
    first = false;
  }
  tried.x = best.x;
  tried.x.head<2>() = white.x.head<2>();
  tried.x[2] = std::log(0.25 * sd[0]), tried.x[3] = std::log(0.25 * sd[1]);
  tried.x = in_box(tried.x);
  if (likelihood.deviance(tried.x, &tried.factors) < best.factors.deviance) std::swap(best, tried);
  return best;
}

}  // namespace

PpkErrorEstimate estimate_ppk_error_model(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                                          const NetworkSelection& selection,
                                          const PpkEstimationOptions& options) {
  PpkErrorEstimate out;
  const RemlMission f = reml_mission(layout, blocks, selection, kEstimationEpochs);
  std::vector<double> t;
  for (std::size_t k : f.layout.gm_chain)
    if (f.fix[k]) t.push_back((*f.layout.points)[k].time_s);
  out.image_scale.assign(f.cameras(), 1), out.image_scale_sd.assign(f.cameras(), 0);
  if (t.size() < 2) return out;
  out.record_s = t.back() - t.front();

  // The white model (scales alone) and the Gauss–Markov model, each at its maximum, both with the
  // cameras' image scales.
  const Likelihood white_family{f, false, &out.evaluations}, gm_family{f, true, &out.evaluations};
  LogParameters white_x = LogParameters::Zero(kPpkParameters + static_cast<Eigen::Index>(f.cameras()));
  white_x[2] = white_x[3] = low(2), white_x[4] = white_x[5] = 0;
  std::vector<int> images = options.image_sigma ? start_image_scales(f, &white_x) : std::vector<int>{};
  const auto with_images = [&](std::vector<int> free) {
    free.insert(free.end(), images.begin(), images.end());
    return free;
  };
  out.image_scale_held.assign(f.cameras(), 0);
  const Fit white = hold_hidden_images(
      white_family, fit(white_family, point_at(white_family, white_x), with_images({0, 1})), {0, 1}, &images,
      &out.image_scale_held);
  // The white fit's own held cameras and free image scales, should the white model be kept.
  const std::vector<int> white_images = images;
  const std::vector<char> white_held = out.image_scale_held;
  const Fit gm = options.white_only ? white
                                    : hold_hidden_images(gm_family,
                                                         fit(gm_family, starting_point(gm_family, white, t),
                                                             with_images({0, 1, 2, 3, 4, 5})),
                                                         {0, 1, 2, 3, 4, 5}, &images, &out.image_scale_held);
  out.likelihood_ratio = white.at.deviance - gm.at.deviance;
  const auto keep_white = [&]() {
    out.white = true;
    out.model = model_of(white.x);
    out.model.gm_sd_h_m = out.model.gm_sd_v_m = out.model.tau_h_s = out.model.tau_v_s = 0;
    images = white_images, out.image_scale_held = white_held;
    const std::vector<int> free = with_images({0, 1});
    const LogParameters sd = log_sd(white, free);
    out.sd = sd_of(white.x, sd);
    image_scales_into(white.x, sd, &out);
    out.sd.gm_sd_h_m = out.sd.gm_sd_v_m = out.sd.tau_h_s = out.sd.tau_v_s =
        std::numeric_limits<double>::quiet_NaN();
    out.on_bound = on_bound(white.x, free);
    return out;
  };
  if (options.white_only || !(out.likelihood_ratio >= kWhiteLikelihoodRatio)) return keep_white();
  // A record shorter than kRecordPerTau·τ̂ pins the increments' rate σ_g²/τ, not σ_g and τ apart
  // (ppk_error_estimation.hpp): hold σ_g at the .pos sd and estimate τ (and s) with it.
  Fit best = gm;
  std::vector<int> free = with_images({0, 1, 4, 5});
  out.gm_sd_held_h = out.record_s < kRecordPerTau * std::exp(gm.x[4]);
  out.gm_sd_held_v = out.record_s < kRecordPerTau * std::exp(gm.x[5]);
  if (!out.gm_sd_held_h) free.push_back(2);
  if (!out.gm_sd_held_v) free.push_back(3);
  const Eigen::Vector2d pos_sd = reported_sd(f);
  if (out.gm_sd_held_h || out.gm_sd_held_v) {
    LogParameters x = gm.x;
    if (out.gm_sd_held_h) x[2] = std::log(pos_sd[0]), x[4] += 2 * (x[2] - gm.x[2]);
    if (out.gm_sd_held_v) x[3] = std::log(pos_sd[1]), x[5] += 2 * (x[3] - gm.x[3]);
    // Started on the ridge: τ scaled with σ_g² (the same rate).
    std::vector<int> ppk;
    for (int i : free)
      if (i < kPpkParameters) ppk.push_back(i);
    best = hold_hidden_images(gm_family, fit(gm_family, point_at(gm_family, x), free), ppk, &images,
                              &out.image_scale_held);
    free = with_images(ppk);
  }
  // The guard: a Gauss–Markov fit the mission does not identify, or whose slow part no fixed PPK
  // solution has, is refused, and the white fit stands.
  std::vector<std::string> refused = unidentified(best.x, free);
  const PpkErrorModel m = model_of(best.x);
  for (int a = 0; a < 2; ++a) {
    const double sd = a == 0 ? m.gm_sd_h_m : m.gm_sd_v_m;
    if (sd > kPlausibleSlowPerPosSd * pos_sd[a])
      refused.push_back(std::string(a == 0 ? "horizontal" : "vertical") + " slow part " +
                        format_number("%.1f", 100 * sd) + " cm is more than " +
                        format_number("%g", kPlausibleSlowPerPosSd) + " times the .pos sd (" +
                        format_number("%.1f", 100 * pos_sd[a]) + " cm)");
  }
  if (!refused.empty()) {
    keep_white();
    out.guard_reasons = std::move(refused);
    return out;
  }
  out.model = m;
  const LogParameters sd = log_sd(best, free);
  out.sd = sd_of(best.x, sd);
  image_scales_into(best.x, sd, &out);
  out.on_bound = on_bound(best.x, free);
  return out;
}

}  // namespace rangecal
