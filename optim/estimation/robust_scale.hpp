#pragma once
// The outlier rule the per-camera bundle, the network and dlt_lmqn share (docs/optimisation.md
// "Outliers"): a whitened residual norm ‖W·e‖ is an outlier above k·max(1, s), with the robust scale
//   s = median‖W·e‖ / √(2 ln 2),
// √(2 ln 2) being the median of a χ₂ variable (the norm of two unit normals), so s ≈ 1 when the
// noise model is right and an over-optimistic σ_px does not flag everything.
#include <vector>

namespace rangecal {

/// median(norms) / √(2 ln 2), the median being the element of rank n/2 (the upper one for an even
/// count); 1 when `norms` is empty. Takes `norms` by value: it is partially sorted.
double robust_scale(std::vector<double> norms);

/// The outlier threshold k·max(1, robust_scale(norms)) in whitened units.
double robust_outlier_threshold(double k, std::vector<double> norms);

}  // namespace rangecal
