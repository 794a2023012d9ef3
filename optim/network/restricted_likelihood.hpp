#pragma once
// The restricted likelihood of the PPK error model on the network, with its derivatives
// (docs/optimisation.md "Correlated PPK errors — estimation"; Patterson & Thompson 1971, REML).
// With the states g integrated out under their AR(1) prior Q and the cameras, points (x) under
// a flat prior, the restricted deviance is
//   D(θ) = −2ℓ_R(θ) = log|R| + log|Q| + log|M| + χ²_min + const,
// R the fixes' white covariance (S·Σ_pos·S per fix), M the normal matrix of (x, g) — the product of
// the eliminations the solve already makes: log|M| = Σ log|V_k| + log|G| + log|S| — and χ²_min the
// linearised least-squares minimum (the Schur identity bᵀM⁻¹b = Σ b_kᵀV_k⁻¹b_k + b̃_gᵀG⁻¹b̃_g +
// b̃_cᵀS⁻¹b̃_c). Image σ and the poles' survey σ are taken as stated.
//
// The parameters θ are in log form: log s_h, log s_v, log σ_h, log σ_v, log τ_h, log τ_v. The
// derivatives are exact for the linearised model:
//   ∂D/∂θ_i = ∂log|R|/∂θ_i + ∂log|Q|/∂θ_i + tr(M⁻¹·∂M/∂θ_i) + êᵀ·∂R⁻¹/∂θ_i·ê + ĝᵀ·∂Q⁻¹/∂θ_i·ĝ
// (the last two at the minimiser, which the minimum does not move to first order), the traces
// from the blocks of M⁻¹ the fixes and the chain touch: Cov(X_k + g_k) per fix and the tridiagonal
// blocks of Σ_gg. The curvature is the average information of Gilmour, Thompson & Cullis
// (Biometrics 51, 1995), AI_ij = ½·wᵢᵀ·P·wⱼ with the working variates wᵢ = ∂Σ/∂θ_i·P·y: for a
// white scale Ṙ·R⁻¹·ê on the fixes, for a Gauss–Markov parameter Q̇·Q⁻¹·ĝ on the states; each
// P·wⱼ is one more solve with the factors the deviance has made. AI is the mean of the observed and
// expected information of ℓ_R, so Newton's step on D is −(2·AI)⁻¹·∇D and Cov(θ̂) = AI⁻¹.
#include <Eigen/Core>
#include <limits>
#include <memory>
#include <vector>

#include "optim/network/network_covariance.hpp"
#include "optim/network/network_parameters.hpp"

namespace rangecal {

/// The model's six parameters in log form (above).
using LogParameters = Eigen::Matrix<double, 6, 1>;
LogParameters log_parameters_of(const PpkErrorModel& model);
PpkErrorModel model_of(const LogParameters& x);

/// The mission's share of the normal equations that no model parameter changes, at the
/// linearisation: the images (and the poles' and cameras' priors) — every point's V, W and gradient
/// without its fix.
struct RemlMission {
  NetworkLayout layout;  ///< every PPK epoch in the chain (its gm_chain order, gm_state)
  std::vector<PointLinearisation> lin;
  std::vector<char> in_solve;             ///< the point is eliminated
  std::vector<char> fix;                  ///< its fix enters, weighed by the model
  std::vector<Eigen::Vector3d> residual;  ///< X − fix (m)
  Eigen::MatrixXd U;
  Eigen::VectorXd gradient;
  double chi2 = 0;
};

/// The mission at the linearisation `blocks` (the white approximation's solution, states zero) over
/// `selection`, its chain thinned to at most `max_states` states, every stride-th: the AR(1) is
/// Markov, so the kept states' prior, chained over the longer steps, is exactly their marginal (the
/// other epochs' fixes and observations are left out). `layout` is any layout of the mission's
/// cameras, points and observations (its own model is not used).
RemlMission reml_mission(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                         const NetworkSelection& selection, std::size_t max_states);

struct RemlEvaluation {
  double deviance = 0;  ///< D(θ); +∞ where the normal equations are not positive definite
  /// ∂D/∂θ and AI (above), over all six parameters (the Gauss–Markov rows zero for the white model);
  /// empty unless asked for.
  LogParameters gradient = LogParameters::Zero();
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  /// ê = fix − X − g at the minimiser per chained fix, in chain order (m); empty unless derivatives
  /// were asked for.
  std::vector<Eigen::Vector3d> corrections;
};

/// The mission's normal equations factored under one model, with the least-squares step there: D,
/// and what its derivatives need without factoring again. Factored again under another model, it
/// keeps its buffers: a search holds two, the point it is at and the one it tries.
struct RemlFactors {
  struct State;  ///< restricted_likelihood.cpp
  std::unique_ptr<State> state;
  double deviance = std::numeric_limits<double>::infinity();
  RemlFactors();
  ~RemlFactors();
  RemlFactors(RemlFactors&&) noexcept;
  RemlFactors& operator=(RemlFactors&&) noexcept;
};

/// D of `model` on the mission into `out` (out->deviance, +∞ where the normal equations are not
/// positive definite); with `chain` false the white model S·Σ_pos·S alone (the model's Gauss–Markov
/// fields unused).
void factor_restricted_likelihood(const RemlMission& mission, const PpkErrorModel& model, bool chain,
                                  RemlFactors* out);

/// D with its gradient and average information (and the corrections) at the model `factors` were
/// made under, on the same mission; D alone where it is +∞.
RemlEvaluation restricted_likelihood_derivatives(const RemlMission& mission, const RemlFactors& factors);

/// Both in one: D of `model`, and with `derivatives` its gradient and average information.
RemlEvaluation evaluate_restricted_likelihood(const RemlMission& mission, const PpkErrorModel& model,
                                              bool chain, bool derivatives);

}  // namespace rangecal
