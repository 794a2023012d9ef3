#pragma once
// The χ²_k quantile by Wilson & Hilferty's cube-root normal approximation (Proc. Natl. Acad. Sci.
// 17, 684–688, 1931): (χ²_k / k)^(1/3) is nearly normal with mean 1 − 2/(9k) and variance 2/(9k).
// Within 1 % of the exact quantile for k ≥ 1 at the 1 % tail (6.58 against 6.63 for k = 1) and
// within 4 % at the 0.1 % tail (11.2 against 10.83), closer as k grows.
#include <cmath>

namespace rangecal {

/// Standard normal quantiles of the upper tails the tests use.
inline constexpr double kNormalQuantile99 = 2.3263478740408408;  ///< upper tail 1 %
inline constexpr double kNormalQuantile999 = 3.090232306167813;  ///< upper tail 0.1 %

/// The χ² quantile of `dof` degrees of freedom (> 0) whose upper tail is that of the standard normal
/// quantile `z` (kNormalQuantile99: the 1 % tail).
inline double chi2_quantile_wilson_hilferty(double dof, double z) {
  const double a = 2.0 / (9.0 * dof);
  const double c = 1 - a + z * std::sqrt(a);
  return dof * c * c * c;
}

}  // namespace rangecal
