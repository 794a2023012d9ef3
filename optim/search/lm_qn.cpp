#include "optim/search/lm_qn.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

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

double max_abs(const VectorXd& v) {
  return v.size() ? v.cwiseAbs().maxCoeff() : 0.0;
}

/// r and J with LmQnResult's evaluation counts; J by central differences when no JacobianFunction
/// is given (their calls of r counted too). Not finite counts as not evaluated.
struct CountedProblem {
  const ResidualFunction& residual;
  const JacobianFunction& jacobian;
  const LmQnOptions& opt;
  LmQnResult* res;

  bool r(const VectorXd& x, VectorXd* out) const {
    ++res->residual_evaluations;
    return residual(x, out) && out->allFinite();
  }
  bool J(const VectorXd& x, MatrixXd* out) const {
    ++res->jacobian_evaluations;
    if (jacobian) return jacobian(x, out) && out->allFinite();
    const ResidualFunction counted = [&](const VectorXd& xx, VectorXd* rr) { return r(xx, rr); };
    return numeric_jacobian(counted, x, opt.numeric_step, opt.typical_x, out);
  }
};

/// The hybrid between iterations (names as in lm_qn.hpp): the iterate with its residual,
/// Jacobian, F, gradient g = Jᵀr and A = JᵀJ; LM's μ and ν; QN's B and trust radius Δ; the mode.
struct HybridState {
  VectorXd x, r, g;
  MatrixXd J, A, B;
  double F = 0, mu = 0, nu = 2;
  double Delta = 0;  // QN trust radius, set at the switch
  bool qn = false;
};

/// A trial point x + h: its residual and F (+∞ if r fails there) and, when the search needs them,
/// its Jacobian and gradient (ok_J).
struct Trial {
  VectorXd x, r, g;
  MatrixXd J;
  double F = 0;
  bool ok_J = false;
};

HybridState start_at(const CountedProblem& p, const VectorXd& x0, const LmQnOptions& opt) {
  HybridState s;
  s.x = x0;
  if (!p.r(s.x, &s.r) || !p.J(s.x, &s.J))
    throw_calibration_error("lm_qn", "the residuals or their Jacobian are not finite at the starting point");
  if (s.J.rows() != s.r.size() || s.J.cols() != x0.size())
    throw_calibration_error("lm_qn", "Jacobian has the wrong shape");
  s.F = 0.5 * s.r.squaredNorm();
  s.g = s.J.transpose() * s.r;
  s.A = s.J.transpose() * s.J;
  s.mu = opt.tau * s.A.diagonal().maxCoeff();
  if (!(s.mu > 0)) s.mu = opt.tau;
  s.B = MatrixXd::Identity(x0.size(), x0.size());
  return s;
}

VectorXd hybrid_step(const HybridState& s) {
  if (!s.qn) {
    // LM step: (JᵀJ + μI)h = −Jᵀr (seed 000, NOTES.md's corrected form).
    MatrixXd Am = s.A;
    Am.diagonal().array() += s.mu;
    return Am.ldlt().solve(-s.g);
  }
  // QN step: B·h = −g, inside the trust radius.
  VectorXd h = s.B.ldlt().solve(-s.g);
  const double hn = h.norm();
  if (hn > s.Delta) h *= s.Delta / hn;
  return h;
}

Trial try_step(const CountedProblem& p, const HybridState& s, const VectorXd& h, const LmQnOptions& opt) {
  Trial t;
  t.x = s.x + h;
  const bool ok_r = p.r(t.x, &t.r);
  t.F = ok_r ? 0.5 * t.r.squaredNorm() : std::numeric_limits<double>::infinity();
  // The hybrid needs J(x_new) for the BFGS update even after a rejected step (MNT); plain LM
  // only needs it after an accepted one.
  if (ok_r && (opt.allow_qn || t.F < s.F)) t.ok_J = p.J(t.x, &t.J);
  if (t.ok_J) t.g = t.J.transpose() * t.r;
  return t;
}

/// BFGS update of B with MNT's y (uses the second-order information LM's JᵀJ lacks).
void bfgs_update(const VectorXd& h, const Trial& t, HybridState* s) {
  const VectorXd y = t.J.transpose() * (t.J * h) + (t.J - s->J).transpose() * t.r;
  const double hy = h.dot(y);
  if (hy > 0) {
    const VectorXd v = s->B * h;
    s->B += y * y.transpose() / hy - v * v.transpose() / h.dot(v);
  }
}

void move_to(const Trial& t, HybridState* s) {
  s->x = t.x, s->r = t.r, s->J = t.J, s->F = t.F, s->g = t.g;
  s->A = s->J.transpose() * s->J;
}

void stop(const char* reason, bool converged, LmQnResult* res) {
  res->stop_reason = reason;
  res->converged = converged;
}

/// An LM iteration after its trial: gain ratio, μ and ν, and the switch to QN (seed 000 LM(5)).
/// False when the search stops.
bool finish_lm_iteration(const VectorXd& h, const Trial& t, const LmQnOptions& opt, HybridState* s,
                         LmQnResult* res) {
  ++res->lm_steps;
  const double pred = 0.5 * h.dot(s->mu * h - s->g);
  const double rho = (t.ok_J && pred > 0) ? (s->F - t.F) / pred : -1;
  if (rho <= 0) {
    res->step_kinds += 'l';
    s->mu *= s->nu;
    s->nu *= 2;
    if (!std::isfinite(s->mu)) {
      stop("no_progress", false, res);
      return false;
    }
    return true;
  }
  res->step_kinds += 'L';
  move_to(t, s);
  s->mu *= std::max(1.0 / 3.0, 1.0 - std::pow(2 * rho - 1, 3));
  s->nu = 2;
  if (max_abs(s->g) <= opt.eps_g) {
    stop("gradient", true, res);
    return false;
  }
  if (opt.allow_qn && max_abs(s->g) < opt.switch_to_qn * s->F) {  // seed 000 LM(5)
    s->qn = true;
    ++res->switches_to_qn;
    const double eps2 = opt.eps_x;
    s->Delta = std::max(1.5 * eps2 * (s->x.norm() + eps2), h.norm());
    if (opt.reset_B_on_switch) s->B.setIdentity();
  }
  return true;
}

/// A QN iteration after its trial: the trust radius and the way back to LM (seed 000 QN(5), MNT).
/// False when the search stops.
bool finish_qn_iteration(const VectorXd& h, const Trial& t, const LmQnOptions& opt, HybridState* s,
                         LmQnResult* res) {
  ++res->qn_steps;
  const double eps2 = opt.eps_x;
  const double g_old = max_abs(s->g);
  bool back_to_lm = false;
  if (t.ok_J && t.F < s->F) {
    res->step_kinds += 'Q';
    const double g_new = max_abs(t.g);
    // seed 000 QN(5): ‖g‖∞ > F → LM; MNT: the gradient stopped decreasing → LM.
    back_to_lm = g_new > t.F || g_new >= g_old;
    if (h.norm() >= 0.99 * s->Delta) s->Delta *= 2;
    move_to(t, s);
    if (max_abs(s->g) <= opt.eps_g) {
      stop("gradient", true, res);
      return false;
    }
  } else {
    res->step_kinds += 'q';
    s->Delta *= 0.5;
    back_to_lm = s->Delta <= eps2 * (s->x.norm() + eps2) || (t.ok_J && max_abs(t.g) >= g_old);
  }
  if (back_to_lm) {
    s->qn = false;
    ++res->switches_to_lm;
  }
  return true;
}

}  // namespace

LmQnResult lm_qn_minimise(const ResidualFunction& residual, const JacobianFunction& jacobian,
                          const VectorXd& x0, const LmQnOptions& opt) {
  LmQnResult res;
  const CountedProblem p{residual, jacobian, opt, &res};
  HybridState s = start_at(p, x0, opt);
  const double eps2 = opt.eps_x;
  res.stop_reason = "max_iterations";
  if (max_abs(s.g) <= opt.eps_g) stop("gradient", true, &res);

  while (!res.converged && res.iterations < opt.max_iterations) {
    ++res.iterations;
    const VectorXd h = hybrid_step(s);
    if (!h.allFinite()) {
      stop("no_progress", false, &res);
      break;
    }
    if (h.norm() <= eps2 * (s.x.norm() + eps2)) {
      stop("step", true, &res);
      break;
    }
    const Trial t = try_step(p, s, h, opt);
    if (opt.allow_qn && t.ok_J) bfgs_update(h, t, &s);
    const bool go_on =
        s.qn ? finish_qn_iteration(h, t, opt, &s, &res) : finish_lm_iteration(h, t, opt, &s, &res);
    if (!go_on) break;
  }
  res.x = s.x;
  res.F = s.F;
  res.residual = s.r;
  res.jacobian = s.J;
  return res;
}

}  // namespace rangecal
