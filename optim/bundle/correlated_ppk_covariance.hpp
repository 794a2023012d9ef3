#pragma once
// The per-camera bundle's covariance under a PPK error model other than its weights
// (docs/optimisation.md "σ under correlated PPK errors"). The bundle weighs every fix as independent,
// under its own .pos covariance Σ_X (optim/bundle/whitening.hpp); the estimate stays that
// white-weighted one, and its covariance becomes the sandwich
//   Cov(θ̂) = N⁻¹·M·N⁻¹,   N = JᵀJ,   M = Jᵀ·Σ_ε·J,
// J the whitened Jacobian (optim/bundle/bundle_covariance.hpp), ε = W_i·(n_i + J_X,i·e_i) the whitened
// residual noise of observation i (pixel noise n_i, world-point error e_i), under the model of
// gnss/track/ppk_error_model.hpp:
//   Cov(ε_i, ε_j) = W_i·(δ_ij·(σ_px²·I + J_X,i·S·Σ_X,i·S·J_X,iᵀ) + J_X,i·D_ij·J_X,jᵀ)·W_jᵀ,
//   D_ij = diag(σ_g,a²·exp(−|t_i − t_j|/τ_a)) per ENU axis a (the GM part, its variance σ_g² included
//   at i = j), S = diag(s_h, s_h, s_v) the white scale.
// A point that is not a PPK fix (a control pole: NaN time) keeps its own Σ_X and no GM part, as in the
// network; a prior row is white with unit variance. With the bundle's own weighting (s = 1, no GM
// part) M = N and the sandwich is N⁻¹: the bundle then skips it.
//
// The GM part of M, Σ_a σ_g,a²·Σ_ij h_i,a·h_j,aᵀ·exp(−|t_i − t_j|/τ_a) with h_i,a = J_iᵀ·W_i·J_X,i·e_a,
// is summed in O(n·p²) by the Markov property of the exponential kernel: over the observations in
// time order, f_k = φ_k·f_{k−1} + h_k (φ_k = exp(−(t_k − t_{k−1})/τ)) is Σ_{j≤k} ρ_kj·h_j, so
//   Σ_ij ρ_ij·h_i·h_jᵀ = X + Xᵀ − Σ_k h_k·h_kᵀ,   X = Σ_k h_k·f_kᵀ
// (the forward recursion; the pairs j > i are Xᵀ's, the diagonal is counted twice).
#include <Eigen/Core>
#include <vector>

#include "gnss/track/ppk_error_model.hpp"
#include "optim/bundle/bundle_observation.hpp"
#include "optim/bundle/bundle_options.hpp"
#include "vision/camera/calibration_result.hpp"
#include "vision/camera/camera_model.hpp"

namespace rangecal {

/// True when `model` is the bundle's own weighting: white scale 1 on both axes, no Gauss–Markov
/// part. The bundle's covariance is then N⁻¹ as it has always been.
bool is_bundle_weighting(const PpkErrorModel& model);

/// Σ_ij h_i·h_jᵀ·exp(−|t_i − t_j|/τ) over the columns h_i of `H` (p × n) at times `t_s` (n,
/// non-decreasing), by the forward recursion above: O(n·p²).
Eigen::MatrixXd exponential_kernel_sum(const Eigen::MatrixXd& H, const std::vector<double>& t_s,
                                       double tau_s);

/// M = Jᵀ·Σ_ε·J (above) for the whitened Jacobian `J` of whitened_system: two rows per used
/// observation (`used`, in order), then the prior rows. `W` the whitening matrices and `cam` the
/// camera they were formed at; each observation's pixel σ is its own (> 0) or `default_sigma_px`.
Eigen::MatrixXd correlated_ppk_meat(const Eigen::MatrixXd& J, const Camera& cam,
                                    const std::vector<BundleObservation>& observations,
                                    const std::vector<char>& used, const std::vector<Eigen::Matrix2d>& W,
                                    double default_sigma_px, const PpkErrorModel& model);

/// N⁻¹·M·N⁻¹ (symmetrised) with M = correlated_ppk_meat, `Ninv` the rank-tested N⁻¹ of `J`; `Ninv`
/// itself when `model` is the bundle's weighting.
Eigen::MatrixXd ppk_sandwich_covariance(const Eigen::MatrixXd& Ninv, const Eigen::MatrixXd& J,
                                        const Camera& cam, const std::vector<BundleObservation>& observations,
                                        const std::vector<char>& used, const std::vector<Eigen::Matrix2d>& W,
                                        double default_sigma_px, const PpkErrorModel& model);

/// How many used observations are on the Gauss–Markov chain (a PPK fix with a time) under `model`:
/// zero unless model.correlated().
int gauss_markov_chained(const std::vector<BundleObservation>& observations, const std::vector<char>& used,
                         const PpkErrorModel& model);

/// The bundle's covariance of a solved camera under `model`, for a model known only after the solve
/// (e.g. estimated by the network): the whitened system at `solution` (its camera, clock offset and
/// rejected observations, as bundle_adjust returned them) with the weights `options` give, the
/// rank-tested N⁻¹ and, unless `model` is the bundle's weighting, the sandwich. The estimate does not
/// depend on the model (the bundle weighs white), so this is the covariance bundle_adjust gives with
/// options.ppk_error = model. `options` must be the ones the solve used (free set, priors, σ_px).
struct BundleCovariance {
  std::vector<CameraParameter> free;
  /// The sandwich (N⁻¹ under the bundle's weighting); empty when rank-deficient.
  Eigen::MatrixXd covariance_unscaled;
  Eigen::MatrixXd covariance_scaled;  ///< × variance_factor
  double chi2 = 0;
  int dof = 0;
  double variance_factor = 0;
  bool rank_deficient = false;
  int gauss_markov_states = 0;  ///< gauss_markov_chained
};
BundleCovariance bundle_covariance_under(const PpkErrorModel& model,
                                         const std::vector<BundleObservation>& observations,
                                         const BundleOptions& options, const CalibrationResult& solution);

}  // namespace rangecal
