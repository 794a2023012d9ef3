#pragma once
// The network's least-squares solve under a correlated PPK error model (docs/optimisation.md
// "Correlated PPK errors — solve"): Gauss–Newton on the normal equations the covariance forms
// (network_covariance.hpp, network_gauss_newton_step), the points eliminated per epoch, the
// Gauss–Markov states by the block-tridiagonal factorisation (gauss_markov_elimination.hpp), the
// cameras' dense system last — O(epochs·cameras²) per iteration. It starts from the robust solve
// of the white approximation (network_adjustment.cpp), where the model is close to linear: each
// step is taken whole when it lowers χ², else halved (at most kMaxHalvings times).
#include "optim/network/network_covariance.hpp"
#include "optim/network/network_parameters.hpp"

namespace rangecal {

inline constexpr int kMaxHalvings = 10;
/// A relative change of χ² within which a whole step has reached the minimum (rounding).
inline constexpr double kRoundingChi2 = 1e-10;

/// `blocks` moved by `scale` × `step` (network_gauss_newton_step); rotations re-based on the moved
/// camera.
NetworkParameterBlocks moved_by_step(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                                     const NetworkStep& step, double scale = 1);

/// Solves in place to relative χ² change `tolerance`; returns the iterations (steps formed).
/// Throws rangecal::Error (calibration) when a step cannot be formed or lowers nothing from the
/// start (a non-finite χ²).
int network_gauss_newton(const NetworkLayout& layout, NetworkParameterBlocks* blocks,
                         const NetworkSelection& selection, double tolerance, int max_iterations);

}  // namespace rangecal
