#pragma once
// Planar-target calibration: Zhang's homography / orthogonality method without skew (seed 001
// §2–3, eqs. 5–16 as corrected in seeds/NOTES.md), then a nonlinear refinement of all parameters.
//
// 1. One homography per view, model plane (X, Y, 0) → pixel (vision/calibration/homography.hpp).
// 2. B = C⁻ᵀC⁻¹ with C = [[α, 0, u0], [0, β, v0], [0, 0, 1]] (no skew ⇒ B12 = 0): two equations per
//    view, v12ᵀb = 0 and (v11 − v22)ᵀb = 0, b = [B11, B22, B13, B23, B33] (seed 001 eq. 8 with
//    NOTES.md's V_ij), solved by SVD in pixel coordinates normalised about the image centre; then
//    u0 = −B13/B11, v0 = −B23/B22, λ = B33 − B13²/B11 − B23²/B22, α = √(λ/B11), β = √(λ/B22).
//    Mapped to docs/conventions.md: f = β·dy, sx = α·dx/(β·dy).
// 3. Per view r1 = κ·C⁻¹h1, r2 = κ·C⁻¹h2, r3 = r1 × r2, t = κ·C⁻¹h3, κ = 2/(‖C⁻¹h1‖ + ‖C⁻¹h2‖), sign
//    so the target is in front (t_z > 0), R projected onto the nearest rotation.
// 4. Radial k1, k2 by linear least squares (seed 001 eqs. 14–16, distorted → undistorted, sensor mm).
// 5. Ceres Levenberg–Marquardt over f, sx, u0, v0, k1, k2 and every view's pose, minimising pixel
//    reprojection error with camera_model.hpp's exact projection.
// World units are the target's (T per view comes back in them); pixels per docs/conventions.md.
#include <Eigen/Core>
#include <vector>

#include "vision/calibration/point_correspondence.hpp"
#include "vision/camera/camera_model.hpp"
#include "vision/camera/sensor_geometry.hpp"

namespace rangecal {

struct PlanarOptions {
  bool estimate_k2 = true;   ///< false: radial k1 only
  bool estimate_sx = true;   ///< false: sx fixed at 1 (square pixels) in the refinement
  bool refine = true;        ///< false: stop after the closed form + linear k1, k2
  int max_iterations = 200;  ///< Ceres LM iterations
};

struct PlanarResult {
  CameraIntrinsics intrinsics;                ///< shared intrinsics (refined when options.refine)
  std::vector<CameraPose> poses;              ///< one per view: Xc = R·[X, Y, 0] + T
  std::vector<Eigen::Matrix3d> homographies;  ///< one per view (‖H‖_F = 1)
  CameraIntrinsics closed_form;               ///< after steps 2–4 (before the refinement)
  double closed_form_rms_px = 0;              ///< RMS reprojection distance before the refinement
  double rms_px = 0;                          ///< RMS reprojection distance (px per point) at the end
  int iterations = 0;                         ///< refinement iterations
};

/// `views[i]` holds view i's points (world Z = 0). Needs ≥ 2 views (4 unknowns of B up to scale,
/// 2 equations per view) in different orientations, ≥ 4 points each (≥ 6 for the refinement).
/// Throws rangecal::Error(calibration) naming the cause: too few views or points, NaN/inf, Z ≠ 0,
/// collinear points, parallel views (singular system), a non-positive-definite B.
PlanarResult planar_calibrate(const std::vector<std::vector<PointCorrespondence>>& views,
                              const SensorGeometry& sensor, const PlanarOptions& options = {});

}  // namespace rangecal
