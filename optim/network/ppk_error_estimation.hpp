#pragma once
// The PPK error model estimated from the mission (docs/optimisation.md "Correlated PPK errors —
// estimation"; Patterson & Thompson 1971): restricted maximum likelihood (REML) of
// the white scale, the Gauss–Markov sd and τ, horizontal and vertical, on the network linearised at
// the robust solution (the likelihood, its gradient and average information:
// restricted_likelihood.hpp). The REML form charges the degrees of freedom the cameras and points
// use, which fitting the corrections' autocorrelation does not (Patterson & Thompson 1971). Image σ and
// the poles' survey σ are taken as stated.
#include <cstddef>
#include <vector>

#include "optim/network/network_parameters.hpp"

namespace rangecal {

/// A record shorter than this many τ cannot separate σ_g from τ (docs/optimisation.md: τ̂ is biased
/// low, 0.4–0.7 of τ at T/τ = 3–10; a Gauss–Markov process over T ≪ τ is an offset the datum absorbs
/// plus a random walk of rate 2σ_g²/τ). Below it, on that axis σ_g is held at the .pos sd — the size
/// RTKLIB gives the whole error (docs/gnss.md "PPK error model") — and τ re-estimated with it, so the
/// rate the record does show is kept: the offset's variance is then the cautious one.
inline constexpr double kRecordPerTau = 4;
/// The estimate uses at most this many epochs of the chain, every stride-th (restricted_likelihood.hpp
/// reml_mission): an evaluation then costs the same on a mission of 20,000 epochs as on one of 2,000,
/// and τ is resolved down to a few times the thinned spacing (docs/optimisation.md "Correlated PPK
/// errors — estimation"). The solve under the estimate uses every epoch.
inline constexpr std::size_t kEstimationEpochs = 2000;
/// 2Δℓ below which the white model is kept: χ²(4 dof) at 95 % (the GM adds sd and τ on two axes).
inline constexpr double kWhiteLikelihoodRatio = 9.49;

/// The REML estimate: the white family (two scales) and the Gauss–Markov family (six parameters)
/// each fitted by Levenberg–Marquardt on the average-information Newton step in log-parameters, the
/// latter from the better of a grid over τ and a start near the white fit; σ from the average
/// information, Cov(log θ) = AI⁻¹. Needs ≥ 2 fixes with a time; otherwise the white model with
/// scale 1 is returned unestimated.
PpkErrorEstimate estimate_ppk_error_model(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                                          const NetworkSelection& selection);

}  // namespace rangecal
