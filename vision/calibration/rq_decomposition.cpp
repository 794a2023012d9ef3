#include "vision/calibration/rq_decomposition.hpp"

#include <Eigen/QR>

namespace rangecal {

RqResult rq_decompose(const Eigen::Matrix3d& M) {
  // With the exchange matrix E (E = Eᵀ = E⁻¹): (E·M)ᵀ = Q·U (QR) gives M = E·Uᵀ·Qᵀ
  // = (E·Uᵀ·E)·(E·Qᵀ), where E·Uᵀ·E is upper triangular and E·Qᵀ orthogonal.
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  E(0, 2) = E(1, 1) = E(2, 0) = 1;
  Eigen::HouseholderQR<Eigen::Matrix3d> qr((E * M).transpose());
  const Eigen::Matrix3d Q = qr.householderQ();
  const Eigen::Matrix3d U = qr.matrixQR().triangularView<Eigen::Upper>();
  RqResult out;
  out.K = E * U.transpose() * E;
  out.R = E * Q.transpose();
  // Make K's diagonal positive: K·D and D·R with D = diag(±1) leave the product unchanged.
  for (int i = 0; i < 3; ++i) {
    if (out.K(i, i) < 0) {
      out.K.col(i) *= -1;
      out.R.row(i) *= -1;
    }
  }
  return out;
}

}  // namespace rangecal
