#pragma once
// The network's variance components estimated from the mission (docs/optimisation.md "Correlated PPK
// errors — estimation" and "Image variance components"): restricted maximum likelihood (REML) of the
// PPK white scale, the Gauss–Markov sd and τ, horizontal and vertical, and of each camera's image
// scale, on the network linearised at the robust solution (the likelihood, its gradient and average
// information: restricted_likelihood.hpp). The REML form charges the degrees of freedom the cameras
// and points use, which fitting the corrections' autocorrelation does not (Patterson & Thompson 1971;
// Harville 1977). The poles' survey σ and the pole picks' σ are taken as stated.
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
/// The guard's plausibility rule: a fixed PPK solution's slow error beyond this many times its .pos
/// sd (rms over the fixes, per axis group) is not a PPK error but the cameras' misfit booked as one.
/// RTKLIB's sd of a fixed epoch is its Kalman covariance under the integers it fixed, optimistic
/// (up to √2 in combined mode, more with correlated multipath) but not by an order of magnitude;
/// published slow PPK errors are 0.8–1.5 cm horizontally, 1.5–3 cm vertically (docs/gnss.md "PPK
/// error model"; docs/references.md).
inline constexpr double kPlausibleSlowPerPosSd = 3;

/// The image scales' box: a camera's centroid σ from 1/10 to 1000 times the stated one (a detector's
/// centroid is not ten times better than stated, and a camera weighed more would make the normal
/// equations stiff without adding what the fixes do not already give).
inline constexpr double kLowestImageScale = 0.1;
inline constexpr double kHighestImageScale = 1000;

/// An image scale whose 1σ exceeds this fraction of it is not determined by the mission: the network
/// warns (its σ still carries the uncertainty the estimate states).
inline constexpr double kUndeterminedImageSigma = 0.25;

struct PpkEstimationOptions {
  bool image_sigma = true;  ///< estimate each camera's image scale (false: held at 1, the stated σ)
  bool white_only = false;  ///< the white family alone (the guard's fallback after a failed check)
};

/// The guard (docs/optimisation.md "The guarded model"): the Gauss–Markov fit is refused — the white
/// fit stands, PpkErrorEstimate::guard_reasons says why — when one of its PPK parameters sits on a
/// bound of the search box (the mission does not identify it) or its slow part exceeds
/// kPlausibleSlowPerPosSd times the .pos sd.
PpkErrorEstimate estimate_ppk_error_model(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                                          const NetworkSelection& selection,
                                          const PpkEstimationOptions& options = {});

}  // namespace rangecal
