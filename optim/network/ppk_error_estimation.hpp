#pragma once
// The PPK error model estimated from the mission (docs/optimisation.md "Correlated PPK errors —
// estimation"; /work/shared/notes/correlated_ppk.md §2c): restricted maximum likelihood (REML) of
// the white scale, the Gauss–Markov sd and τ, horizontal and vertical, on the network linearised at
// the robust solution. With the states g integrated out under their AR(1) prior P and the cameras,
// points (x) under a flat prior, the restricted deviance is
//   −2ℓ_R(θ) = log|W| + log|P| + log|M| + χ²_min + const,
// W the fixes' white covariance (S·Σ_pos·S per fix), M the normal matrix of (x, g) — the product of
// the eliminations the solve already makes: log|M| = Σ log|V_k| + log|G| + log|S| — and χ²_min the
// linearised least-squares minimum (the Schur identity bᵀM⁻¹b = Σ b_kᵀV_k⁻¹b_k + b̃_gᵀG⁻¹b̃_g +
// b̃_cᵀS⁻¹b̃_c). The REML form charges the degrees of freedom the cameras and points use, which fitting
// the corrections' autocorrelation does not (correlated_ppk.md §2c). Image σ and the poles' survey σ
// are taken as stated.
#include <cstddef>
#include <vector>

#include "optim/network/network_parameters.hpp"

namespace rangecal {

/// A record shorter than this many τ cannot separate σ_g from τ (correlated_ppk.md §2c: τ̂ is biased
/// low, 0.4–0.7 of τ at T/τ = 3–10; a Gauss–Markov process over T ≪ τ is an offset the datum absorbs
/// plus a random walk of rate 2σ_g²/τ). Below it, on that axis σ_g is held at the .pos sd — the size
/// RTKLIB gives the whole error (docs/gnss.md "PPK error model") — and τ re-estimated with it, so the
/// rate the record does show is kept: the offset's variance is then the cautious one.
inline constexpr double kRecordPerTau = 4;
/// The estimate uses at most this many epochs of the chain, every stride-th (ppk_error_estimation.cpp
/// thin_chain): an evaluation then costs the same on a mission of 20,000 epochs as on one of 2,000,
/// and τ is resolved down to a few times the thinned spacing (docs/optimisation.md "Correlated PPK
/// errors — estimation"). The solve under the estimate uses every epoch.
inline constexpr std::size_t kEstimationEpochs = 2000;
/// 2Δℓ below which the white model is kept: χ²(4 dof) at 95 % (the GM adds sd and τ on two axes).
inline constexpr double kWhiteLikelihoodRatio = 9.49;

/// −2ℓ_R of `model` (correlated or white) at the linearisation `blocks` (the white approximation's
/// solution, states zero) over `selection`. `layout` is any layout of the mission's cameras, points
/// and observations (its own model is not used).
double restricted_deviance(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                           const NetworkSelection& selection, const PpkErrorModel& model);

/// The REML estimate (Nelder–Mead in log-parameters from a grid over τ; σ from the deviance's
/// numerical Hessian, Cov(log θ) = 2·H⁻¹). Needs ≥ 2 fixes with a time; otherwise the white model
/// with scale 1 is returned unestimated.
PpkErrorEstimate estimate_ppk_error_model(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                                          const NetworkSelection& selection);

}  // namespace rangecal
