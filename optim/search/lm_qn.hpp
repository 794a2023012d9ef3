#pragma once
// Levenberg–Marquardt / quasi-Newton hybrid of seed 000 §3 (after Madsen, Nielsen & Tingleff,
// "Methods for non-linear least squares problems", 2004, §3.5 "a hybrid method: L–M and
// quasi-Newton"), on Eigen, for min F(x) = ½‖r(x)‖².
//
// Reading of the seed (NOTES.md fixes its misprints):
//   Θ(ξ)  the objective value F = ½‖r‖² (seed 000 eq. 11, "目标函数值"), Θ′ its gradient g = Jᵀr.
//   LM step       (JᵀJ + μI)·h = −Jᵀr, μ by Madsen–Nielsen: μ0 = τ·max diag(JᵀJ); gain ratio
//                 ρ = (F(x) − F(x+h)) / (½hᵀ(μh − g)); accepted (ρ > 0): μ ← μ·max(1/3, 1 − (2ρ − 1)³),
//                 ν ← 2; rejected: μ ← μ·ν, ν ← 2ν.
//   LM → QN       when ‖g‖∞ < 0.02·F after an accepted LM step (F not going to zero: LM is in its
//                 slow linear phase; seed 000 step LM(5)).
//   QN step       B·h = −g, B the BFGS approximation of F's Hessian, started at I (seed 000 QN(1));
//                 as in MNT the step is kept inside a trust radius Δ (Δ ← max(Δ, ‖h_LM‖) at the
//                 switch, halved on a failed step, doubled after a long successful one) — without it
//                 B = I's first step −g is meaningless in mixed units.
//                 B is BFGS-updated after every step, LM or QN, with MNT's y = J_newᵀJ_new·h +
//                 (J_new − J)ᵀ·r_new (skipped unless hᵀy > 0); `reset_B_on_switch` restarts it at I
//                 at each LM → QN switch as seed 000 literally says.
//   QN → LM       when ‖g_new‖∞ > F_new (seed 000 QN(5)), or the QN step failed to reduce F and Δ
//                 shrank below the step tolerance, or (MNT) ‖g‖∞ stopped decreasing.
//   Stop          ‖Δx‖ < ε_x·(‖x‖ + ε_x) (seed 000's ‖ξ_{i+1} − ξ_i‖ < ε, made relative as MNT),
//                 ‖g‖∞ < ε_g, or max_iterations.
// Plain LM is the same code with `allow_qn = false`.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace rangecal {

/// Residual r(x) (m-vector). Return false if r cannot be evaluated at x (treated as F = +∞).
using ResidualFunction = std::function<bool(const Eigen::VectorXd& x, Eigen::VectorXd* r)>;
/// Jacobian ∂r/∂x (m × n). Return false on failure.
using JacobianFunction = std::function<bool(const Eigen::VectorXd& x, Eigen::MatrixXd* J)>;

struct LmQnOptions {
  bool allow_qn = true;            ///< false → plain Levenberg–Marquardt
  double tau = 1e-3;               ///< μ0 = τ·max diag(JᵀJ)
  double switch_to_qn = 0.02;      ///< LM → QN when ‖g‖∞ < switch_to_qn·F (seed 000)
  bool reset_B_on_switch = false;  ///< seed-literal B = I at every switch (default: MNT, B kept)
  double eps_x = 1e-12;            ///< step tolerance ε (relative, see above)
  double eps_g = 1e-14;            ///< gradient tolerance ‖g‖∞
  int max_iterations = 500;
  /// Numeric Jacobian (when no JacobianFunction is given): central differences with step
  /// h_j = numeric_step·max(|x_j|, typical_x_j) (typical_x defaults to 1).
  double numeric_step = 1e-6;
  Eigen::VectorXd typical_x;
};

struct LmQnResult {
  Eigen::VectorXd x;
  double F = 0;  ///< ½‖r‖² at x
  Eigen::VectorXd residual;
  Eigen::MatrixXd jacobian;  ///< J at x
  int iterations = 0;        ///< steps attempted (accepted or not)
  int lm_steps = 0;          ///< iterations that were LM steps
  int qn_steps = 0;          ///< iterations that were QN steps
  int switches_to_qn = 0;
  int switches_to_lm = 0;
  long residual_evaluations = 0;  ///< calls of r (including those inside numeric Jacobians)
  long jacobian_evaluations = 0;
  std::string step_kinds;   ///< one letter per iteration: 'L' LM, 'Q' QN (lower case: rejected)
  std::string stop_reason;  ///< "step", "gradient", "max_iterations", "no_progress"
  bool converged = false;   ///< stopped on step or gradient tolerance
};

/// Minimises ½‖r(x)‖² from x0. jacobian may be empty (numeric central differences).
/// Throws rangecal::Error (calibration) if r cannot be evaluated at x0 or is not finite there.
LmQnResult lm_qn_minimise(const ResidualFunction& residual, const JacobianFunction& jacobian,
                          const Eigen::VectorXd& x0, const LmQnOptions& opt = {});

/// Central-difference Jacobian of r at x (2n evaluations of r), steps as in LmQnOptions.
bool numeric_jacobian(const ResidualFunction& residual, const Eigen::VectorXd& x, double rel_step,
                      const Eigen::VectorXd& typical_x, Eigen::MatrixXd* J);

}  // namespace rangecal
