#pragma once
// The network's cost functors, written like the equations (Ceres autodiff through the templated
// camera model, vision/camera/camera_model.hpp). Camera blocks as the per-camera bundle's
// (optim/bundle/reprojection_cost.hpp: intrinsics, distortion, pose, clock); one more block per
// point, X (ENU m), eliminated first by the Schur solver.
#include <ceres/rotation.h>

#include <Eigen/Core>

#include "optim/bundle/reprojection_cost.hpp"

namespace rangecal {

/// Image residual of camera c at point k, in units of the pixel σ:
///   X  = X_k + offset − v·δ_c                      (the lamp at camera c's exposure)
///   Xc = exp([w]×)·R0·(X − C)                       (docs/conventions.md, T = −R·C)
///   (u, v) = project_camera_point(intr, dist, Xc)   (seed 002 eqs. 6–7 + seed 000 eq. 7)
///   r = ((u, v) − (u_obs, v_obs)) / σ_px
/// Unlike the per-camera bundle, the PPK noise is not folded into the weight: X_k is a parameter
/// with its own prior (NetworkPointPrior), so the camera sees only its centroid noise.
struct NetworkReprojectionResidual {
  Eigen::Vector3d offset;
  Eigen::Vector3d vel;
  Eigen::Vector2d uv;
  double inv_sigma_px;
  Eigen::Matrix3d R0;
  double dx_mm, dy_mm;

  template <typename T>
  bool operator()(const T* intr, const T* dist, const T* pose, const T* clock, const T* point,
                  T* residual) const {
    T d[3];
    for (int i = 0; i < 3; ++i) d[i] = point[i] + T(offset[i]) - T(vel[i]) * clock[0] - pose[3 + i];
    T q[3];
    for (int i = 0; i < 3; ++i) q[i] = T(R0(i, 0)) * d[0] + T(R0(i, 1)) * d[1] + T(R0(i, 2)) * d[2];
    T xc[3];
    ceres::AngleAxisRotatePoint(pose, q, xc);
    T u, v;
    if (!project_camera_point(intr, dist, dx_mm, dy_mm, xc, &u, &v)) return false;
    residual[0] = (u - T(uv.x())) * T(inv_sigma_px);
    residual[1] = (v - T(uv.y())) * T(inv_sigma_px);
    return true;
  }
};

/// Prior of a point (PPK fix or pole survey):  r = L⁻¹·(X − X̄),  L·Lᵀ = Σ_prior (full 3×3).
struct NetworkPointPrior {
  Eigen::Vector3d prior;
  Eigen::Matrix3d whiten;  ///< L⁻¹

  template <typename T>
  bool operator()(const T* point, T* residual) const {
    const T e[3] = {point[0] - T(prior.x()), point[1] - T(prior.y()), point[2] - T(prior.z())};
    for (int i = 0; i < 3; ++i)
      residual[i] = T(whiten(i, 0)) * e[0] + T(whiten(i, 1)) * e[1] + T(whiten(i, 2)) * e[2];
    return true;
  }
};

inline constexpr int kPointBlockSize = 3;

}  // namespace rangecal
