#pragma once
// The rotation nearest a 3×3 matrix in the Frobenius norm (Zhang 1998, appendix C): with M = U·S·Vᵀ
// its SVD, R = U·Vᵀ, the last column of U negated when that would be a reflection (det < 0). The
// planar method orthonormalises each view's [r1 r2 r1×r2] with it, Tsai's step 1 its rows r1..r6
// (TsaiOrthonormalisation::svd): both rotations come out of a linear solve, orthonormal only up to
// noise.
#include <Eigen/Core>

namespace rangecal {

Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& M);

}  // namespace rangecal
