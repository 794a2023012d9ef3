#include "optim/bundle/reprojection_cost_function.hpp"

#include "optim/bundle/projection_jacobian.hpp"

namespace rangecal {
namespace {

/// Block b's columns of the whitened 2 × 18 Jacobian, row-major as Ceres wants them.
template <int Size>
void write_block(const Eigen::Matrix<double, 2, kBundleParameterCount>& J, int first, double* out) {
  for (int c = 0; c < Size; ++c) out[c] = J(0, first + c), out[Size + c] = J(1, first + c);
}

}  // namespace

bool ReprojectionCostFunction::Evaluate(double const* const* parameters, double* residuals,
                                        double** jacobians) const {
  Eigen::Vector2d uv;
  ProjectionJacobian pj;
  if (!project_with_jacobian(parameters[0], parameters[1], parameters[2], parameters[3][0], r_.R0, r_.dx_mm,
                             r_.dy_mm, r_.Xw, r_.vel, &uv, jacobians ? &pj : nullptr))
    return false;
  const Eigen::Vector2d r = r_.W * (uv - r_.uv);
  residuals[0] = r.x(), residuals[1] = r.y();
  if (!jacobians) return true;
  const Eigen::Matrix<double, 2, kBundleParameterCount> J = r_.W * pj.camera;
  constexpr int kDist = kIntrinsicsBlockSize, kPose = kDist + kDistortionBlockSize,
                kClock = kPose + kPoseBlockSize;
  if (jacobians[0]) write_block<kIntrinsicsBlockSize>(J, 0, jacobians[0]);
  if (jacobians[1]) write_block<kDistortionBlockSize>(J, kDist, jacobians[1]);
  if (jacobians[2]) write_block<kPoseBlockSize>(J, kPose, jacobians[2]);
  if (jacobians[3]) write_block<kClockBlockSize>(J, kClock, jacobians[3]);
  return true;
}

}  // namespace rangecal
