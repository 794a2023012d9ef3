#pragma once
// Nelder–Mead simplex minimisation (Nelder & Mead 1965; coefficients of Lagarias et al., SIAM J.
// Optim. 9(1), 1998: reflection 1, expansion 2, contraction ½, shrink ½), for a few smooth
// parameters whose derivatives are costly: the PPK error model's likelihood
// (optim/network/ppk_error_estimation.hpp).
#include <Eigen/Core>
#include <functional>

namespace rangecal {

struct NelderMeadResult {
  Eigen::VectorXd x;
  double value = 0;
  int evaluations = 0;
};

/// Minimises f from x0, the first simplex x0 + step_i·e_i. Stops when the simplex's values span
/// less than `tolerance` (absolute) or after `max_evaluations`. f may return +∞ (infeasible).
NelderMeadResult nelder_mead(const std::function<double(const Eigen::VectorXd&)>& f,
                             const Eigen::VectorXd& x0, const Eigen::VectorXd& step, double tolerance,
                             int max_evaluations);

}  // namespace rangecal
