#include "optim/search/lm_qn.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "config/error.hpp"

namespace rangecal {

using Eigen::MatrixXd;
using Eigen::VectorXd;

bool numeric_jacobian(const ResidualFunction& residual, const VectorXd& x, double rel_step,
                      const VectorXd& typical_x, MatrixXd* J) {
  const Eigen::Index n = x.size();
  VectorXd xp = x, rp, rm;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double typ = typical_x.size() == n ? std::abs(typical_x[j]) : 1.0;
    const double h = rel_step * std::max(std::abs(x[j]), typ > 0 ? typ : 1.0);
    xp[j] = x[j] + h;
    if (!residual(xp, &rp)) return false;
    xp[j] = x[j] - h;
    if (!residual(xp, &rm)) return false;
    xp[j] = x[j];
    if (j == 0) J->resize(rp.size(), n);
    J->col(j) = (rp - rm) / (2 * h);
  }
  return J->allFinite();
}

namespace {

/// r and J with the evaluations counted in the result (a numeric J's residuals included).
struct CountedProblem {
  const ResidualFunction& residual;
  const JacobianFunction& jacobian;
  const LmQnOptions& opt;
  LmQnResult* res;

  bool eval_r(const VectorXd& x, VectorXd* r) const {
    ++res->residual_evaluations;
    return residual(x, r) && r->allFinite();
  }
  bool eval_J(const VectorXd& x, MatrixXd* J) const {
    ++res->jacobian_evaluations;
    if (jacobian) return jacobian(x, J) && J->allFinite();
    const ResidualFunction counted = [this](const VectorXd& xx, VectorXd* r) { return eval_r(xx, r); };
    return numeric_jacobian(counted, x, opt.numeric_step, opt.typical_x, J);
  }
};

/// The minimiser's state: the current point and its r, J, F, g = Jᵀr, A = JᵀJ; LM's damping μ, ν;
/// the BFGS matrix B, QN's trust radius Δ, and which step is next.
struct LmQnState {
  VectorXd x, r, g;
  MatrixXd J, A, B;
  double F = 0, mu = 0, nu = 2;
  double Delta = 0;  // QN trust radius, set at the switch
  bool qn = false;
};

/// The trial point x + h: its residual, F (+∞ when r fails), and when evaluated its J and g.
struct Trial {
  VectorXd xn, rn, gn;
  MatrixXd Jn;
  double Fn = 0;
  bool ok_J = false;
};

double gnorm(const VectorXd& v) {
  return v.size() ? v.cwiseAbs().maxCoeff() : 0.0;
}

/// The LM step (JᵀJ + μI)h = −Jᵀr (seed 000, NOTES.md's corrected form), or the QN step B·h = −g
/// inside the trust radius.
VectorXd next_step(const LmQnState& st) {
  if (!st.qn) {
    MatrixXd Am = st.A;
    Am.diagonal().array() += st.mu;
    return Am.ldlt().solve(-st.g);
  }
  VectorXd h = st.B.ldlt().solve(-st.g);
  const double hn = h.norm();
  if (hn > st.Delta) h *= st.Delta / hn;
  return h;
}

Trial evaluate_trial(const CountedProblem& p, const LmQnState& st, const VectorXd& h) {
  Trial t;
  t.xn = st.x + h;
  const bool ok_r = p.eval_r(t.xn, &t.rn);
  t.Fn = ok_r ? 0.5 * t.rn.squaredNorm() : std::numeric_limits<double>::infinity();
  // The hybrid needs J(x_new) for the BFGS update even after a rejected step (MNT); plain LM
  // only needs it after an accepted one.
  if (ok_r && (p.opt.allow_qn || t.Fn < st.F)) t.ok_J = p.eval_J(t.xn, &t.Jn);
  if (t.ok_J) t.gn = t.Jn.transpose() * t.rn;
  return t;
}

/// BFGS update of B with MNT's y (uses the second-order information LM's JᵀJ lacks).
void update_bfgs(const VectorXd& h, const Trial& t, LmQnState* st) {
  const VectorXd y = t.Jn.transpose() * (t.Jn * h) + (t.Jn - st->J).transpose() * t.rn;
  const double hy = h.dot(y);
  if (hy > 0) {
    const VectorXd v = st->B * h;
    st->B += y * y.transpose() / hy - v * v.transpose() / h.dot(v);
  }
}

/// Moves the state to the trial point.
void accept(Trial&& t, LmQnState* st) {
  st->x = std::move(t.xn);
  st->r = std::move(t.rn);
  st->J = std::move(t.Jn);
  st->F = t.Fn;
  st->g = std::move(t.gn);
  st->A = st->J.transpose() * st->J;
}

/// Stops on the gradient tolerance; true when it did.
bool gradient_converged(const LmQnState& st, const LmQnOptions& opt, LmQnResult* res) {
  if (!(gnorm(st.g) <= opt.eps_g)) return false;
  res->stop_reason = "gradient";
  res->converged = true;
  return true;
}

/// An LM iteration's outcome (gain ratio, damping, switch to QN); true when the search stops.
bool finish_lm_step(const VectorXd& h, Trial&& t, const LmQnOptions& opt, LmQnState* st, LmQnResult* res) {
  ++res->lm_steps;
  const double eps2 = opt.eps_x;
  const double pred = 0.5 * h.dot(st->mu * h - st->g);
  const double rho = (t.ok_J && pred > 0) ? (st->F - t.Fn) / pred : -1;
  if (rho > 0) {
    res->step_kinds += 'L';
    accept(std::move(t), st);
    st->mu *= std::max(1.0 / 3.0, 1.0 - std::pow(2 * rho - 1, 3));
    st->nu = 2;
    if (gradient_converged(*st, opt, res)) return true;
    if (opt.allow_qn && gnorm(st->g) < opt.switch_to_qn * st->F) {  // seed 000 LM(5)
      st->qn = true;
      ++res->switches_to_qn;
      st->Delta = std::max(1.5 * eps2 * (st->x.norm() + eps2), h.norm());
      if (opt.reset_B_on_switch) st->B.setIdentity();
    }
    return false;
  }
  res->step_kinds += 'l';
  st->mu *= st->nu;
  st->nu *= 2;
  if (std::isfinite(st->mu)) return false;
  res->stop_reason = "no_progress";
  return true;
}

/// A QN iteration's outcome (trust radius, switch back to LM); true when the search stops.
bool finish_qn_step(const VectorXd& h, Trial&& t, const LmQnOptions& opt, LmQnState* st, LmQnResult* res) {
  ++res->qn_steps;
  const double eps2 = opt.eps_x;
  const double g_old = gnorm(st->g);
  bool back_to_lm = false;
  if (t.ok_J && t.Fn < st->F) {
    res->step_kinds += 'Q';
    const double g_new = gnorm(t.gn);
    // seed 000 QN(5): ‖g‖∞ > F → LM; MNT: the gradient stopped decreasing → LM.
    back_to_lm = g_new > t.Fn || g_new >= g_old;
    if (h.norm() >= 0.99 * st->Delta) st->Delta *= 2;
    accept(std::move(t), st);
    if (gradient_converged(*st, opt, res)) return true;
  } else {
    res->step_kinds += 'q';
    st->Delta *= 0.5;
    back_to_lm = st->Delta <= eps2 * (st->x.norm() + eps2) || (t.ok_J && gnorm(t.gn) >= g_old);
  }
  if (back_to_lm) {
    st->qn = false;
    ++res->switches_to_lm;
  }
  return false;
}

}  // namespace

LmQnResult lm_qn_minimise(const ResidualFunction& residual, const JacobianFunction& jacobian,
                          const VectorXd& x0, const LmQnOptions& opt) {
  LmQnResult res;
  const CountedProblem problem{residual, jacobian, opt, &res};
  const Eigen::Index n = x0.size();
  LmQnState st;
  st.x = x0;
  if (!problem.eval_r(st.x, &st.r) || !problem.eval_J(st.x, &st.J))
    throw_calibration_error("lm_qn", "the residuals or their Jacobian are not finite at the starting point");
  if (st.J.rows() != st.r.size() || st.J.cols() != n)
    throw_calibration_error("lm_qn", "Jacobian has the wrong shape");
  st.F = 0.5 * st.r.squaredNorm();
  st.g = st.J.transpose() * st.r;
  st.A = st.J.transpose() * st.J;
  st.mu = opt.tau * st.A.diagonal().maxCoeff();
  if (!(st.mu > 0)) st.mu = opt.tau;
  st.B = MatrixXd::Identity(n, n);
  const double eps2 = opt.eps_x;

  res.stop_reason = "max_iterations";
  gradient_converged(st, opt, &res);
  while (!res.converged && res.iterations < opt.max_iterations) {
    ++res.iterations;
    const VectorXd h = next_step(st);
    if (!h.allFinite()) {
      res.stop_reason = "no_progress";
      break;
    }
    if (h.norm() <= eps2 * (st.x.norm() + eps2)) {
      res.stop_reason = "step";
      res.converged = true;
      break;
    }
    Trial t = evaluate_trial(problem, st, h);
    if (opt.allow_qn && t.ok_J) update_bfgs(h, t, &st);
    const bool stop = st.qn ? finish_qn_step(h, std::move(t), opt, &st, &res)
                            : finish_lm_step(h, std::move(t), opt, &st, &res);
    if (stop) break;
  }
  res.x = st.x;
  res.F = st.F;
  res.residual = st.r;
  res.jacobian = st.J;
  return res;
}

}  // namespace rangecal
