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

LmQnResult lm_qn_minimise(const ResidualFunction& residual, const JacobianFunction& jacobian,
                          const VectorXd& x0, const LmQnOptions& opt) {
  LmQnResult res;
  const Eigen::Index n = x0.size();
  auto eval_r = [&](const VectorXd& x, VectorXd* r) {
    ++res.residual_evaluations;
    return residual(x, r) && r->allFinite();
  };
  auto eval_J = [&](const VectorXd& x, MatrixXd* J) {
    ++res.jacobian_evaluations;
    if (jacobian) return jacobian(x, J) && J->allFinite();
    const ResidualFunction counted = [&](const VectorXd& xx, VectorXd* r) { return eval_r(xx, r); };
    return numeric_jacobian(counted, x, opt.numeric_step, opt.typical_x, J);
  };

  VectorXd x = x0, r;
  MatrixXd J;
  if (!eval_r(x, &r) || !eval_J(x, &J))
    throw_calibration_error("lm_qn", "the residuals or their Jacobian are not finite at the starting point");
  if (J.rows() != r.size() || J.cols() != n) throw_calibration_error("lm_qn", "Jacobian has the wrong shape");
  double F = 0.5 * r.squaredNorm();
  VectorXd g = J.transpose() * r;
  MatrixXd A = J.transpose() * J;
  double mu = opt.tau * A.diagonal().maxCoeff();
  if (!(mu > 0)) mu = opt.tau;
  double nu = 2;
  MatrixXd B = MatrixXd::Identity(n, n);
  double Delta = 0;  // QN trust radius, set at the switch
  bool qn = false;
  const double eps2 = opt.eps_x;

  auto gnorm = [](const VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; };
  res.stop_reason = "max_iterations";
  if (gnorm(g) <= opt.eps_g) {
    res.stop_reason = "gradient";
    res.converged = true;
  }

  while (!res.converged && res.iterations < opt.max_iterations) {
    ++res.iterations;
    VectorXd h;
    if (!qn) {
      // LM step: (JᵀJ + μI)h = −Jᵀr (seed 000, NOTES.md's corrected form).
      MatrixXd Am = A;
      Am.diagonal().array() += mu;
      h = Am.ldlt().solve(-g);
    } else {
      // QN step: B·h = −g, inside the trust radius.
      h = B.ldlt().solve(-g);
      const double hn = h.norm();
      if (hn > Delta) h *= Delta / hn;
    }
    if (!h.allFinite()) {
      res.stop_reason = "no_progress";
      break;
    }
    if (h.norm() <= eps2 * (x.norm() + eps2)) {
      res.stop_reason = "step";
      res.converged = true;
      break;
    }
    const VectorXd xn = x + h;
    VectorXd rn;
    const bool ok_r = eval_r(xn, &rn);
    const double Fn = ok_r ? 0.5 * rn.squaredNorm() : std::numeric_limits<double>::infinity();
    MatrixXd Jn;
    bool ok_J = false;
    // The hybrid needs J(x_new) for the BFGS update even after a rejected step (MNT); plain LM
    // only needs it after an accepted one.
    if (ok_r && (opt.allow_qn || Fn < F)) ok_J = eval_J(xn, &Jn);
    VectorXd gn;
    if (ok_J) gn = Jn.transpose() * rn;

    if (opt.allow_qn && ok_J) {
      // BFGS update of B with MNT's y (uses the second-order information LM's JᵀJ lacks).
      const VectorXd y = Jn.transpose() * (Jn * h) + (Jn - J).transpose() * rn;
      const double hy = h.dot(y);
      if (hy > 0) {
        const VectorXd v = B * h;
        B += y * y.transpose() / hy - v * v.transpose() / h.dot(v);
      }
    }

    if (!qn) {
      ++res.lm_steps;
      const double pred = 0.5 * h.dot(mu * h - g);
      const double rho = (ok_J && pred > 0) ? (F - Fn) / pred : -1;
      if (rho > 0) {
        res.step_kinds += 'L';
        x = xn, r = rn, J = Jn, F = Fn, g = gn;
        A = J.transpose() * J;
        mu *= std::max(1.0 / 3.0, 1.0 - std::pow(2 * rho - 1, 3));
        nu = 2;
        if (gnorm(g) <= opt.eps_g) {
          res.stop_reason = "gradient";
          res.converged = true;
          break;
        }
        if (opt.allow_qn && gnorm(g) < opt.switch_to_qn * F) {  // seed 000 LM(5)
          qn = true;
          ++res.switches_to_qn;
          Delta = std::max(1.5 * eps2 * (x.norm() + eps2), h.norm());
          if (opt.reset_B_on_switch) B.setIdentity();
        }
      } else {
        res.step_kinds += 'l';
        mu *= nu;
        nu *= 2;
        if (!std::isfinite(mu)) {
          res.stop_reason = "no_progress";
          break;
        }
      }
    } else {
      ++res.qn_steps;
      const double g_old = gnorm(g);
      const bool better = ok_J && Fn < F;
      bool back_to_lm = false;
      if (better) {
        res.step_kinds += 'Q';
        const double g_new = gnorm(gn);
        // seed 000 QN(5): ‖g‖∞ > F → LM; MNT: the gradient stopped decreasing → LM.
        back_to_lm = g_new > Fn || g_new >= g_old;
        if (h.norm() >= 0.99 * Delta) Delta *= 2;
        x = xn, r = rn, J = Jn, F = Fn, g = gn;
        A = J.transpose() * J;
        if (gnorm(g) <= opt.eps_g) {
          res.stop_reason = "gradient";
          res.converged = true;
          break;
        }
      } else {
        res.step_kinds += 'q';
        Delta *= 0.5;
        back_to_lm = Delta <= eps2 * (x.norm() + eps2) || (ok_J && gnorm(gn) >= g_old);
      }
      if (back_to_lm) {
        qn = false;
        ++res.switches_to_lm;
      }
    }
  }
  res.x = x;
  res.F = F;
  res.residual = r;
  res.jacobian = J;
  return res;
}

}  // namespace rangecal
