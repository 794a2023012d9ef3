#pragma once
// RQ decomposition of a 3×3 matrix, M = K·R with K upper triangular with positive diagonal and R
// orthogonal — the step that splits a DLT projection matrix's left 3×3 block into intrinsics and
// rotation (seed 000 eqs. 3–6; Hartley & Zisserman §6.2.4). det(R) = sign(det M).
#include <Eigen/Core>

namespace rangecal {

struct RqResult {
  Eigen::Matrix3d K;  ///< upper triangular, K(i,i) > 0
  Eigen::Matrix3d R;  ///< orthogonal; a proper rotation iff det(M) > 0
};

/// Requires M invertible (the caller checks); uses Householder QR of the row-reversed transpose.
RqResult rq_decompose(const Eigen::Matrix3d& M);

}  // namespace rangecal
