#pragma once
// The demo's accuracy bars (docs/accuracy_analysis.md "Quality bars"): tests of the calibration
// against the simulated truth that a correct calibration, with honest σ, passes with probability
// ≥ 1 − kDemoBarsAlpha whatever the noise drawn. Each family (parameter errors, check-pole errors)
// gets half of α, split over its tests by Bonferroni's union bound, which holds however the tests
// are correlated (the check poles share the cameras' errors; f and the centre are correlated):
// - a parameter: z² = ((estimate − truth)/σ)² ≤ χ²₁ quantile of tail α/(2·N_parameters);
// - a check pole: dᵀ·C⁻¹·d ≤ χ²₃ quantile of tail α/(2·N_poles), d its error against the truth, C
//   the covariance the intersection predicts for it;
// - the absolute bar (mean ΔR ≤ 1 cm, seed 002's figure being 2.5 cm) only where the predicted
//   covariances support it at the same level: every pole's largest eigenvalue λ satisfies
//   λ·χ²₃(tail α/(2·N_poles)) ≤ (1 cm)², so that P(any ΔR > 1 cm) ≤ α/2 (mean ΔR > 1 cm needs one).
#include <string>
#include <vector>

#include "pipeline/demo/demo.hpp"

namespace rangecal {

/// The probability that a correct calibration fails at least one bar.
inline constexpr double kDemoBarsAlpha = 0.01;
/// The absolute check-pole bar (m): mean ΔR against the truth.
inline constexpr double kDemoMeanDrBar_m = 0.010;

struct DemoBar {
  std::string line;  ///< what is printed: the figure, its limit, ok / FAIL / not applied
  /// false: a correct calibration fails this with probability < its share of α (an absolute bar the
  /// predicted σ does not support is not applied, and passes)
  bool pass = true;
};

struct DemoBars {
  std::vector<DemoBar> bars;
  double parameter_z_limit = 0;  ///< |z| limit of each parameter
  double pole_chi2_limit = 0;    ///< dᵀC⁻¹d limit of each check pole
  bool pass() const;
};

/// The bars of `r` for the bundle and for r.method (when not the bundle): f, k1 and the centre of
/// every camera, and every check pole triangulated by the method's cameras.
DemoBars demo_accuracy_bars(const DemoResults& r);

}  // namespace rangecal
