#pragma once
// The symmetric part ½(M + Mᵀ) of a covariance or normal matrix accumulated in floating point,
// whose two triangles differ by rounding: eigen-solvers and Cholesky read one triangle, and a
// covariance written out should be symmetric to the bit.
#include <Eigen/Core>

namespace rangecal {

template <typename Derived>
typename Derived::PlainObject symmetric_part(const Eigen::MatrixBase<Derived>& m) {
  return 0.5 * (m + m.transpose());
}

}  // namespace rangecal
