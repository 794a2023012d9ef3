#pragma once
// The PPK error model of the fixes (docs/gnss.md "PPK error model", docs/optimisation.md
// "Correlated PPK errors"): per ENU axis, the error of a fix is
//   e_k = w_k + g_k,    w_k white, Cov(w_k) = S·Σ_pos,k·S,   S = diag(s_h, s_h, s_v),
//   g_k first-order Gauss–Markov: E[g_k g_j] = σ_g²·exp(−|t_k − t_j|/τ), axes uncorrelated,
// Σ_pos,k the fix's own covariance from the .pos sd columns (which RTKLIB, and rangecal's simulator,
// report as the whole error: docs/references.md "Correlated PPK errors"). E and N share the horizontal
// values, U has its own. The GM part is carried as one state per epoch and axis, chained by the exact
// discretisation for any spacing (Brown & Hwang 2012, the first-order Gauss–Markov process):
//   g_0 ~ N(0, σ_g²),   g_k = φ_k·g_{k−1} + ν_k,   φ_k = exp(−Δt_k/τ),   ν_k ~ N(0, σ_g²·(1 − φ_k²)),
// so a gap between flights of many τ decouples them (φ → 0) and the stationary variance is σ_g² at
// every epoch. With no GM part (σ_g = 0) and s = 1 the model is the white one the network has always
// used: each fix independent under its own Σ_pos.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace rangecal {

struct PpkErrorModel {
  double white_scale_h = 1;  ///< s_h: the white sd as a fraction of the .pos sd, E and N
  double white_scale_v = 1;  ///< s_v: the same, U
  double gm_sd_h_m = 0;      ///< σ_g of E and N (m)
  double gm_sd_v_m = 0;      ///< σ_g of U (m)
  double tau_h_s = 0;        ///< τ of E and N (s)
  double tau_v_s = 0;        ///< τ of U (s)

  /// A Gauss–Markov part (on every axis: a model correlated on some axes only is refused where it
  /// is read, pipeline/mission): the network then carries the GM states.
  bool correlated() const { return gm_sd_h_m > 0 && gm_sd_v_m > 0 && tau_h_s > 0 && tau_v_s > 0; }
  /// σ_g per ENU axis (m).
  Eigen::Vector3d gm_sd() const { return {gm_sd_h_m, gm_sd_h_m, gm_sd_v_m}; }
  /// τ per ENU axis (s).
  Eigen::Vector3d tau() const { return {tau_h_s, tau_h_s, tau_v_s}; }
  /// S per ENU axis.
  Eigen::Vector3d white_scale() const { return {white_scale_h, white_scale_h, white_scale_v}; }
};

/// φ = exp(−|dt|/τ) for a step of dt seconds of a Gauss–Markov process of time constant τ (s): the
/// AR(1) chain's coefficient above, and the correlation of two of its values dt apart.
inline double gauss_markov_transition(double dt_s, double tau_s) {
  return std::exp(-std::abs(dt_s) / tau_s);
}

/// φ per ENU axis for a step of dt seconds: exp(−|dt|/τ).
inline Eigen::Vector3d gauss_markov_transition(const PpkErrorModel& m, double dt_s) {
  const Eigen::Vector3d tau = m.tau();
  Eigen::Vector3d phi;
  for (int a = 0; a < 3; ++a) phi[a] = gauss_markov_transition(dt_s, tau[a]);
  return phi;
}

/// 1/σ of the chain's residuals per ENU axis: of the first state, 1/σ_g, when `phi` is null; else of
/// the step g_k − φ·g_{k−1}, 1/(σ_g·√(1 − φ²)).
inline Eigen::Vector3d gauss_markov_weight(const PpkErrorModel& m, const Eigen::Vector3d* phi) {
  const Eigen::Vector3d sd = m.gm_sd();
  Eigen::Vector3d w;
  for (int a = 0; a < 3; ++a)
    w[a] = 1 / (sd[a] * (phi ? std::sqrt(std::max(1e-300, 1 - (*phi)[a] * (*phi)[a])) : 1.0));
  return w;
}

/// How many independent looks at the Gauss–Markov error the fixes at times `t_s` (ascending) give,
/// per ENU axis: 1ᵀ·R⁻¹·1 with R their correlation matrix, exp(−|t_i − t_j|/τ) — the information
/// the fixes hold about a common offset, in units of one fix (docs/accuracy_analysis.md: ≈ T/(2τ) over
/// a flight of T ≫ τ; a gap of many τ starts a new look). From the chain's residual form,
/// 1ᵀ·R⁻¹·1 = 1 + Σ_k (1 − φ_k)/(1 + φ_k). Zero for no fixes.
template <class Times>
Eigen::Vector3d gauss_markov_looks(const PpkErrorModel& m, const Times& t_s) {
  if (t_s.empty()) return Eigen::Vector3d::Zero();
  Eigen::Vector3d looks = Eigen::Vector3d::Ones();
  for (std::size_t k = 1; k < t_s.size(); ++k) {
    const Eigen::Vector3d phi = gauss_markov_transition(m, t_s[k] - t_s[k - 1]);
    looks += (Eigen::Vector3d::Ones() - phi).cwiseQuotient(Eigen::Vector3d::Ones() + phi);
  }
  return looks;
}

/// The model estimated from the mission itself (optim/network/ppk_error_estimation.hpp; docs/optimisation.md
/// "Correlated PPK errors — estimation").
struct PpkErrorEstimate {
  PpkErrorModel model;  ///< what the network then weighs the fixes by
  /// 1σ of each estimated parameter (same fields, same units); NaN where the parameter was held.
  PpkErrorModel sd;
  bool white = false;           ///< the likelihood-ratio test kept the white model (no GM part)
  double likelihood_ratio = 0;  ///< 2·(ℓ_GM − ℓ_white), restricted log-likelihoods at their maxima
  double record_s = 0;          ///< T: first to last fix in the chain (s)
  /// Per axis (horizontal, vertical): T < kRecordPerTau·τ̂, so σ_g was held at the .pos sd and τ re-estimated
  /// with it (ppk_error_estimation.hpp).
  bool gm_sd_held_h = false, gm_sd_held_v = false;
  int evaluations = 0;  ///< likelihood evaluations
  /// Per camera (the network's order), s_c: its lamp centroids' σ as a multiple of the stated σ
  /// (restricted_likelihood.hpp), estimated with the model; 1 where the camera has no centroid in the
  /// estimate. And its 1σ (0 where not estimated).
  std::vector<double> image_scale, image_scale_sd;
  /// Per camera: its image scale went to the box's lower bound — its centroids hidden by the fixes'
  /// own error — and was held at 1, the stated σ (ppk_error_estimation.cpp hold_hidden_images).
  std::vector<char> image_scale_held;
  /// Per camera: F, the variance inflation of its image residuals correlated in time; the network
  /// weighed its centroids by the scale's σ·√F (optim/network/image_time_correlation.hpp). Empty or 1: not
  /// measured or not correlated.
  std::vector<double> image_time_factor;
  /// Why the Gauss–Markov fit was refused and the white fit kept (ppk_error_estimation.hpp, the
  /// guard); empty when it was accepted or the likelihood-ratio test kept the white model.
  std::vector<std::string> guard_reasons;
  /// The estimated parameters on a bound of the search box that the mission does not determine
  /// (any bound of τ or of an image scale, the upper bound of a white scale or sd), named, with their
  /// value. A white scale or sd at its lower bound is a variance component at zero, not among them.
  std::vector<std::string> on_bound;
};

/// Below this many independent looks the datum rests on few PPK samples (docs/accuracy_analysis.md
/// "Correlated PPK errors"): the run warns.
inline constexpr double kFewPpkLooks = 10;

}  // namespace rangecal
