#pragma once
// The bundle's projection (reprojection_cost.hpp) with its first derivatives written out, for the
// solvers' inner loops; the autodiff functors stay the definition, and
// tests/unit/optim/projection_jacobian_test.cpp holds the two equal. Chain, outermost last:
//   X  = Xw − v·δ                               ∂X/∂δ = −v
//   Xc = R(w)·R0·(X − C)                        ∂Xc/∂X = R(w)·R0 = −∂Xc/∂C
//                                               ∂Xc/∂w = −[Xc]×·J_l(w)
//   (xu, yu) = f·(Xc/Zc, Yc/Zc)                 (seed 002 eq. 6)
//   (xd, yd): xd + Δ(xd; k) = xu                ∂xd/∂xu = J_F⁻¹,  ∂xd/∂k = −J_F⁻¹·∂Δ/∂k
//                                               (implicit function theorem; J_F = I + ∂Δ/∂xd,
//                                                Δ of seed 000 eq. 7)
//   u = u0 + sx·xd/dx,  v = v0 + yd/dy
// J_l(w) = I + (1 − cos θ)/θ²·[w]× + (θ − sin θ)/θ³·[w]×² is the left Jacobian of SO(3)
// (exp([w + ε]×) ≈ exp([J_l(w)·ε]×)·exp([w]×); Solà et al. 2018, "A micro Lie theory", SO(3)).
#include <Eigen/Core>

#include "optim/bundle/reprojection_cost.hpp"

namespace rangecal {

/// A projected pixel and its derivatives.
struct ProjectionJacobian {
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  ///< pixel (px)
  /// ∂(u, v)/∂θ over the camera's 18 parameters in canonical order (f sx u0 v0 k1 k2 k3 p1 p2 a1
  /// a2 wx wy wz CE CN CU clock_offset; px per mm, px, px⁻¹·mm^k, px/rad, px/m, px/s).
  Eigen::Matrix<double, 2, kBundleParameterCount> camera;
  Eigen::Matrix<double, 2, 3> world;  ///< ∂(u, v)/∂Xw (px/m)
};

/// The parts of the chain that depend on the rotation alone: R = R(w)·R0 and J_l(w). The network
/// computes them once per camera and evaluation instead of once per observation.
struct PoseRotation {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();   ///< world ENU → camera
  Eigen::Matrix3d Jl = Eigen::Matrix3d::Identity();  ///< left Jacobian of SO(3) at w
};

/// R(w)·R0 and J_l(w) of the rotation vector `w` (rad) about `R0`; without `with_left_jacobian`,
/// J_l is left at I (the pixel alone does not need it).
PoseRotation pose_rotation(const double* w, const Eigen::Matrix3d& R0, bool with_left_jacobian = true);

/// As below, with the rotation given (`rotation` of pose[0..2]) and the centre `center` (ENU m).
bool project_with_jacobian(const double* intr, const double* dist, const PoseRotation& rotation,
                           const double* center, double clock_s, double dx_mm, double dy_mm,
                           const Eigen::Vector3d& Xw, const Eigen::Vector3d& vel, Eigen::Vector2d* uv,
                           ProjectionJacobian* jacobian);

/// Projects the world point Xw (ENU m, at the epoch; the lamp moves with `vel` m/s) through the
/// camera of the four bundle blocks (intr, dist, pose about R0, clock offset δ in s). With
/// `jacobian` null only `uv` is computed. False behind the camera or when the distortion inverse
/// does not converge (as project_camera_point).
bool project_with_jacobian(const double* intr, const double* dist, const double* pose, double clock_s,
                           const Eigen::Matrix3d& R0, double dx_mm, double dy_mm, const Eigen::Vector3d& Xw,
                           const Eigen::Vector3d& vel, Eigen::Vector2d* uv, ProjectionJacobian* jacobian);

}  // namespace rangecal
