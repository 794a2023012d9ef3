#pragma once
// A symmetric positive-definite system S·x = b solved through the LDLT of its Jacobi-scaled form:
// S = d⁻¹·(L·D·Lᵀ)·d⁻¹ with d = diag(S)^(−1/2), so that the factorised matrix has a unit diagonal.
// The network's camera columns span decades of scale (a focal length in pixels beside a
// distortion coefficient and a rotation in radians; the f–distance ridge of a narrow lens), and
// the pivots and the test of positive definiteness are then taken on one scale. The network's
// Gauss–Newton step and its restricted likelihood (docs/optimisation.md) both solve the cameras'
// reduced system with it.
#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace rangecal {

class JacobiScaledLdlt {
 public:
  /// Factors the symmetric `S`; false when it is not positive definite (the factorisation failed
  /// or a pivot of D is not positive). A diagonal element ≤ 0 is scaled as 1e-300.
  bool compute(const Eigen::MatrixXd& S) {
    d_ = S.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    ldlt_.compute(d_.asDiagonal() * S * d_.asDiagonal());
    return ldlt_.info() == Eigen::Success && (ldlt_.vectorD().array() > 0).all();
  }

  /// `log_det` + log|S|, log|S| = Σ log D_i − 2·Σ log d_i, added in that order.
  double add_log_determinant(double log_det) const {
    return log_det + ldlt_.vectorD().array().log().sum() - 2 * d_.array().log().sum();
  }

  /// S⁻¹·B = d·(LDLᵀ)⁻¹·(d·B).
  template <typename Derived>
  typename Derived::PlainObject solve(const Eigen::MatrixBase<Derived>& B) const {
    return d_.asDiagonal() * ldlt_.solve(d_.asDiagonal() * B);
  }

  /// S⁻¹ = d·(LDLᵀ)⁻¹·d.
  Eigen::MatrixXd inverse() const { return d_.asDiagonal() * ldlt_.solve(Eigen::MatrixXd(d_.asDiagonal())); }

 private:
  Eigen::VectorXd d_;  ///< diag(S)^(−1/2)
  Eigen::LDLT<Eigen::MatrixXd> ldlt_;
};

}  // namespace rangecal
