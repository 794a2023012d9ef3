#pragma once
// The restricted likelihood of the network's variance components, with its derivatives
// (docs/optimisation.md "Correlated PPK errors — estimation" and "Image variance components";
// Patterson & Thompson 1971, REML):
// the PPK error model (gnss/track/ppk_error_model.hpp) and each camera's image scale s_c — the σ of its lamp
// centroids as a multiple of the stated σ, so that their covariance is s_c²·σ_px²·I. With the states g
// integrated out under their AR(1) prior Q and the cameras, points (x) under a flat prior, the
// restricted deviance is
//   D(θ) = −2ℓ_R(θ) = log|R| + log|Q| + log|M| + χ²_min + const,
// R the observations' white covariance (S·Σ_pos·S per fix, s_c²·σ_px² per centroid coordinate), M the
// normal matrix of (x, g) — the product of the eliminations the solve already makes: log|M| =
// Σ log|V_k| + log|G| + log|S| — and χ²_min the linearised least-squares minimum (the Schur
// identity bᵀM⁻¹b = Σ b_kᵀV_k⁻¹b_k + b̃_gᵀG⁻¹b̃_g + b̃_cᵀS⁻¹b̃_c). Estimating the image scales with the
// PPK model gives the cameras' misfit a place of its own: with the centroid σ held at a stated value
// far below the real scatter, the likelihood books the misfit as PPK error (Koch 1999 §3.6 on
// variance components; Teunissen & Amiri-Simkooei 2008 on least-squares variance component
// estimation). Pole picks (observations with their own σ) and the poles' survey σ are taken as
// stated.
//
// The parameters θ are in log form: log s_h, log s_v, log σ_h, log σ_v, log τ_h, log τ_v, then
// log s_c per camera. The derivatives are exact for the linearised model:
//   ∂D/∂θ_i = ∂log|R|/∂θ_i + ∂log|Q|/∂θ_i + tr(M⁻¹·∂M/∂θ_i) + êᵀ·∂R⁻¹/∂θ_i·ê + ĝᵀ·∂Q⁻¹/∂θ_i·ĝ
// (the last two at the minimiser, which the minimum does not move to first order), the traces
// from the blocks of M⁻¹ the fixes, the chain and the images touch: Cov(X_k + g_k) per fix, the
// tridiagonal blocks of Σ_gg, and per camera tr(M⁻¹·N_c) over its normal equations N_c; for an
// image scale ∂D/∂log s_c = 2·(n_c − tr(M⁻¹·N_c) − χ²_c,min), whose zero is Förstner's iterated
// variance component (n_c − tr(M⁻¹·N_c) the camera's redundancy). The curvature is the average
// information of Gilmour, Thompson & Cullis (Biometrics 51, 1995), AI_ij = ½·wᵢᵀ·P·wⱼ with the
// working variates wᵢ = ∂Σ/∂θ_i·P·y: for a white scale Ṙ·R⁻¹·ê on the fixes, for a Gauss–Markov
// parameter Q̇·Q⁻¹·ĝ on the states, for an image scale 2·ê_c on the camera's centroids; each P·wⱼ
// is one more solve with the factors the deviance has made. AI is the mean of the observed and
// expected information of ℓ_R, so Newton's step on D is −(2·AI)⁻¹·∇D and Cov(θ̂) = AI⁻¹.
#include <Eigen/Core>
#include <limits>
#include <memory>
#include <vector>

#include "optim/network/network_covariance.hpp"
#include "optim/network/network_parameters.hpp"

namespace rangecal {

/// The PPK model's six parameters in log form, then the cameras' image scales (above): 6 + cameras
/// entries, or 6 (every image scale 1).
using LogParameters = Eigen::VectorXd;
inline constexpr int kPpkParameters = 6;
/// x of `model` with `cameras` image scales of 1 (log 0) after it.
LogParameters log_parameters_of(const PpkErrorModel& model, std::size_t cameras = 0);
/// The PPK model of x's first six entries.
PpkErrorModel model_of(const LogParameters& x);
/// Camera c's image scale s_c in x (1 where x has none).
double image_scale_of(const LogParameters& x, std::size_t c);

/// One camera's lamp centroids of one point at the linearisation, at their stated σ: its share of
/// V_k, W_k and the gradient, which the camera's image scale divides by s_c².
struct ImageGroup {
  std::size_t camera = 0;
  Eigen::Matrix3d V = Eigen::Matrix3d::Zero();
  CameraPointBlock W;
  Eigen::Vector3d grad_point = Eigen::Vector3d::Zero();
};

/// The mission's normal equations at the linearisation: what no variance component changes (the
/// pole picks, the poles' and cameras' priors: every point's V, W and gradient without its fix and
/// its lamp centroids) and, apart, each camera's lamp centroids at their stated σ.
struct RemlMission {
  NetworkLayout layout;  ///< every PPK epoch in the chain (its gm_chain order, gm_state)
  std::vector<PointLinearisation> lin;
  std::vector<char> in_solve;             ///< the point is eliminated
  std::vector<char> fix;                  ///< its fix enters, weighed by the model
  std::vector<Eigen::Vector3d> residual;  ///< X − fix (m)
  Eigen::MatrixXd U;
  Eigen::VectorXd gradient;
  double chi2 = 0;
  /// Per point, its lamp centroids by camera; their J_cᵀJ_c (joint columns, block-diagonal by
  /// camera), gradient on the cameras, and per camera χ² and residual count n_c.
  std::vector<std::vector<ImageGroup>> images;
  Eigen::MatrixXd image_U;
  Eigen::VectorXd image_gradient;
  std::vector<double> image_chi2;
  std::vector<int> image_rows;
  std::size_t cameras() const { return image_rows.size(); }
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
  /// ∂D/∂θ and AI (above), over all 6 + cameras parameters (the Gauss–Markov rows zero for the white
  /// model, a camera's zero where it has no lamp centroid); empty unless asked for.
  LogParameters gradient;
  Eigen::MatrixXd information;
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

/// D at `x` on the mission into `out` (out->deviance, +∞ where the normal equations are not
/// positive definite); with `chain` false the white model S·Σ_pos·S alone (x's Gauss–Markov
/// entries unused).
void factor_restricted_likelihood(const RemlMission& mission, const LogParameters& x, bool chain,
                                  RemlFactors* out);

/// D with its gradient and average information (and the corrections) at the x `factors` were
/// made under, on the same mission; D alone where it is +∞.
RemlEvaluation restricted_likelihood_derivatives(const RemlMission& mission, const RemlFactors& factors);

/// Both in one: D at `x`, and with `derivatives` its gradient and average information.
RemlEvaluation evaluate_restricted_likelihood(const RemlMission& mission, const LogParameters& x, bool chain,
                                              bool derivatives);

}  // namespace rangecal
