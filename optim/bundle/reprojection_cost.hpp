#pragma once
// The bundle's cost functors, written like the equations (Ceres autodiff; the projection is the
// templated camera model of vision/camera/camera_model.hpp). A camera is four Ceres parameter
// blocks holding the vocabulary's parameters in canonical order (vision/camera/camera_parameters.hpp):
//   intrinsics  f sx u0 v0              (project_camera_point's intr order)
//   distortion  k1 k2 k3 p1 p2 a1 a2    (Distortion::as_array order)
//   pose        wx wy wz CE CN CU       (rotation perturbation about R0, camera centre)
//   clock       clock_offset
#include <ceres/rotation.h>

#include <Eigen/Core>

#include "vision/camera/camera_model.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal {

inline constexpr int kIntrinsicsBlockSize = 4;
inline constexpr int kDistortionBlockSize = 7;
inline constexpr int kPoseBlockSize = 6;
inline constexpr int kClockBlockSize = 1;
static_assert(kIntrinsicsBlockSize + kDistortionBlockSize + kPoseBlockSize + kClockBlockSize ==
                  kBundleParameterCount,
              "the blocks hold the bundle's parameters");
static_assert(index_of(CameraParameter::k1) == kIntrinsicsBlockSize &&
                  index_of(CameraParameter::wx) == kIntrinsicsBlockSize + kDistortionBlockSize &&
                  index_of(CameraParameter::clock_offset) ==
                      kIntrinsicsBlockSize + kDistortionBlockSize + kPoseBlockSize,
              "the blocks follow the canonical order");

/// Whitened reprojection residual of one point, the definition the per-camera bundle and the
/// network share:
///   X  = Xw − v·δ                                   (the lamp at the true exposure time, δ the clock
///                                                    offset; optim/bundle/bundle_observation.hpp)
///   Xc = exp([w]×)·R0·(X − C)                       (docs/conventions.md, T = −R·C)
///   (u, v) = project_camera_point(intr, dist, Xc)   (seed 002 eqs. 6–7 + seed 000 eq. 7)
///   r = W·((u, v) − (u_obs, v_obs)),  W = L⁻¹, C_eff = L·Lᵀ  (optim/bundle/whitening.hpp)
/// With a fifth block, the network's point X_k (ENU m, docs/optimisation.md "Network bundle"), Xw
/// is X_k + Xw: `Xw` is then the offset of camera c's frame time from the epoch, and W = I/σ_px
/// (the point's PPK noise is its own prior, not folded into the weight).
struct ReprojectionResidual {
  Eigen::Vector3d Xw;
  Eigen::Vector3d vel;
  Eigen::Vector2d uv;
  Eigen::Matrix2d W;
  Eigen::Matrix3d R0;
  double dx_mm, dy_mm;

  template <typename T>
  bool operator()(const T* intr, const T* dist, const T* pose, const T* clock, T* residual) const {
    const T X[3] = {T(Xw.x()), T(Xw.y()), T(Xw.z())};
    return at(intr, dist, pose, clock, X, residual);
  }

  template <typename T>
  bool operator()(const T* intr, const T* dist, const T* pose, const T* clock, const T* point,
                  T* residual) const {
    const T X[3] = {point[0] + T(Xw.x()), point[1] + T(Xw.y()), point[2] + T(Xw.z())};
    return at(intr, dist, pose, clock, X, residual);
  }

  /// The residual of the lamp at world point X (before the clock-offset motion).
  template <typename T>
  bool at(const T* intr, const T* dist, const T* pose, const T* clock, const T* X, T* residual) const {
    T d[3];
    for (int i = 0; i < 3; ++i) d[i] = X[i] - T(vel[i]) * clock[0] - pose[3 + i];
    T q[3];
    for (int i = 0; i < 3; ++i) q[i] = T(R0(i, 0)) * d[0] + T(R0(i, 1)) * d[1] + T(R0(i, 2)) * d[2];
    T xc[3];
    ceres::AngleAxisRotatePoint(pose, q, xc);
    T u, v;
    if (!project_camera_point(intr, dist, dx_mm, dy_mm, xc, &u, &v)) return false;
    const T eu = u - T(uv.x()), ev = v - T(uv.y());
    residual[0] = T(W(0, 0)) * eu + T(W(0, 1)) * ev;
    residual[1] = T(W(1, 0)) * eu + T(W(1, 1)) * ev;
    return true;
  }
};

/// Principal-point prior: ((u0 − ū0)/σ, (v0 − v̄0)/σ).
struct PrincipalPointPrior {
  Eigen::Vector2d p;
  double sigma;
  template <typename T>
  bool operator()(const T* intr, T* residual) const {
    residual[0] = (intr[2] - T(p.x())) / T(sigma);
    residual[1] = (intr[3] - T(p.y())) / T(sigma);
    return true;
  }
};

/// Camera-centre prior: (C − C̄)/σ per ENU axis.
struct CenterPrior {
  Eigen::Vector3d c;
  Eigen::Vector3d sigma;
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    for (int i = 0; i < 3; ++i) residual[i] = (pose[3 + i] - T(c[i])) / T(sigma[i]);
    return true;
  }
};

}  // namespace rangecal
