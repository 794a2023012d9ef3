#include "optim/bundle/projection_jacobian.hpp"

#include <ceres/rotation.h>

#include <cmath>

namespace rangecal {
namespace {

using Eigen::Matrix2d;
using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

Matrix3d skew(const Vector3d& a) {
  Matrix3d s;
  s << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return s;
}

/// J_l(w), the left Jacobian of SO(3); its Taylor series below θ = 1e-4 (error < θ⁴/120).
Matrix3d left_jacobian(const Vector3d& w) {
  const double t2 = w.squaredNorm();
  const Matrix3d W = skew(w);
  if (t2 < 1e-8) return Matrix3d::Identity() + 0.5 * W + (1.0 / 6.0) * W * W;
  const double t = std::sqrt(t2);
  return Matrix3d::Identity() + (1 - std::cos(t)) / t2 * W + (t - std::sin(t)) / (t2 * t) * W * W;
}

}  // namespace

PoseRotation pose_rotation(const double* w, const Matrix3d& R0, bool with_left_jacobian) {
  PoseRotation r;
  Matrix3d Rw;
  ceres::AngleAxisToRotationMatrix(w, ceres::ColumnMajorAdapter3x3(Rw.data()));
  r.R = Rw * R0;
  if (with_left_jacobian) r.Jl = left_jacobian(Vector3d(w[0], w[1], w[2]));
  return r;
}

bool project_with_jacobian(const double* intr, const double* dist, const double* pose, double clock_s,
                           const Matrix3d& R0, double dx_mm, double dy_mm, const Vector3d& Xw,
                           const Vector3d& vel, Vector2d* uv, ProjectionJacobian* jacobian) {
  // The pixel alone needs no J_l.
  return project_with_jacobian(intr, dist, pose_rotation(pose, R0, jacobian != nullptr), pose + 3, clock_s,
                               dx_mm, dy_mm, Xw, vel, uv, jacobian);
}

bool project_with_jacobian(const double* intr, const double* dist, const PoseRotation& rotation,
                           const double* center, double clock_s, double dx_mm, double dy_mm,
                           const Vector3d& Xw, const Vector3d& vel, Vector2d* uv,
                           ProjectionJacobian* jacobian) {
  const Matrix3d& R = rotation.R;
  const Vector3d C(center[0], center[1], center[2]);
  const Vector3d xc = R * (Xw - vel * clock_s - C);
  if (!(xc.z() > 0)) return false;
  const double f = intr[0], sx = intr[1], a = xc.x() / xc.z(), b = xc.y() / xc.z();
  double xd = 0, yd = 0;
  const bool ok = distort_sensor_newton(dist, f * a, f * b, &xd, &yd);
  *uv = Vector2d(intr[2] + sx * xd / dx_mm, intr[3] + yd / dy_mm);
  if (!ok) return false;
  if (!jacobian) return true;
  jacobian->uv = *uv;

  // J_F = I + ∂Δ/∂(xd, yd) (vision/camera/camera_model.hpp) and ∂Δ/∂k (seed 000 eq. 7 differentiated).
  Eigen::Matrix<double, 2, 2, Eigen::RowMajor> JF;
  distortion_jacobian(dist, xd, yd, JF.data());
  const double r2 = xd * xd + yd * yd, r4 = r2 * r2, r6 = r4 * r2;
  Eigen::Matrix<double, 2, kDistortionBlockSize> dDelta;
  dDelta << xd * r2, xd * r4, xd * r6, r2 + 2 * xd * xd, 2 * xd * yd, 0, 0,  //
      yd * r2, yd * r4, yd * r6, 2 * xd * yd, r2 + 2 * yd * yd, xd, yd;
  const Matrix2d PJ = Vector2d(sx / dx_mm, 1 / dy_mm).asDiagonal() * JF.inverse();  // ∂uv/∂(xu, yu)

  Eigen::Matrix<double, 2, 3> dxu_dxc;
  dxu_dxc << 1, 0, -a, 0, 1, -b;
  const Eigen::Matrix<double, 2, 3> A = PJ * dxu_dxc * (f / xc.z());  // ∂uv/∂Xc
  const Eigen::Matrix<double, 2, 3> AR = A * R;                       // ∂uv/∂X

  auto& J = jacobian->camera;
  J.col(0) = PJ * Vector2d(a, b);
  J.col(1) = Vector2d(xd / dx_mm, 0);
  J.col(2) = Vector2d(1, 0);
  J.col(3) = Vector2d(0, 1);
  J.middleCols<kDistortionBlockSize>(kIntrinsicsBlockSize) = -PJ * dDelta;
  constexpr int kW = kIntrinsicsBlockSize + kDistortionBlockSize;
  J.middleCols<3>(kW) = -A * skew(xc) * rotation.Jl;
  J.middleCols<3>(kW + 3) = -AR;
  J.col(kW + kPoseBlockSize) = -AR * vel;
  jacobian->world = AR;
  return true;
}

}  // namespace rangecal
