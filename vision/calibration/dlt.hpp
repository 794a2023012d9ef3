#pragma once
// Direct linear transformation (seed 000 §2.1, eqs. 1–6; Hartley & Zisserman alg. 7.1) with
// Hartley normalisation and RANSAC, and the split of the projection matrix into rangecal's camera.
//
//   λ·[u, v, 1]ᵀ = P·[Xw, 1]ᵀ,   P = K·[R | −R·C],   K = [[fx, s, u0], [0, fy, v0], [0, 0, 1]]
//   (eq. 1; G·M' = 0 of eq. 2, two rows per point, solved as the right singular vector of the
//   smallest singular value after normalising pixels to mean distance √2 and world points to √3).
// P is split by RQ decomposition (eqs. 3–6) into K, R (proper rotation, world → camera) and C, and
// mapped to docs/conventions.md's model: f = fy·dy, sx = fx·dx/(fy·dy), (u0, v0) = (K13, K23); the skew s is
// not in rangecal's model and is reported, not kept. The sign of P is chosen so det(K·R) > 0 and the
// points lie in front of the camera. The DLT model has no distortion: with a distorted lens, f and the
// principal point absorb part of it, and vision/calibration/linear_distortion.hpp (eq. 8) gives initial
// values.
//
// World points in any length unit (C and T come back in it); pixels per docs/conventions.md.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "vision/calibration/point_correspondence.hpp"
#include "vision/camera/camera_model.hpp"
#include "vision/camera/sensor_geometry.hpp"

namespace rangecal {

using ProjectionMatrix = Eigen::Matrix<double, 3, 4>;

struct DltOptions {
  bool ransac = true;                ///< false: one least-squares fit on all points
  double inlier_threshold_px = 2.0;  ///< RANSAC: inlier iff reprojection distance < this (px)
  int max_iterations = 2000;         ///< RANSAC sample cap
  double confidence = 0.999;         ///< RANSAC stops once an all-inlier sample was this likely drawn
  std::uint64_t seed = 1;            ///< RANSAC sampling seed (same seed → same result)
};

/// K, R, C of a projection matrix (seed 000 eqs. 3–6 via RQ).
struct KrcDecomposition {
  Eigen::Matrix3d K;  ///< upper triangular, K(2,2) = 1, positive diagonal
  Eigen::Matrix3d R;  ///< world → camera, proper rotation
  Eigen::Vector3d C;  ///< camera centre (world units)
};

struct DltResult {
  ProjectionMatrix P;  ///< ‖P‖_F = 1, det(P₃ₓ₃) > 0 (pixels ∝ P·[Xw; 1])
  KrcDecomposition krc;
  double skew_px = 0;                 ///< K(0,1), dropped from `camera`
  Camera camera;                      ///< f, sx, u0, v0 from K; pose R, T = −R·C; no distortion
  std::vector<std::size_t> inliers;   ///< indices into the input, ascending
  std::vector<std::size_t> outliers;  ///< the rest, ascending
  int ransac_iterations = 0;          ///< samples drawn (0 without RANSAC)
  double rms_px = 0;                  ///< RMS reprojection distance of P over the inliers
  double camera_rms_px = 0;           ///< the same for `camera` (differs by the dropped skew)
};

/// Normalised linear DLT over all `pts` (≥ 6, non-coplanar). Throws rangecal::Error(calibration) on
/// a degenerate or singular system.
ProjectionMatrix dlt_projection_matrix(const std::vector<PointCorrespondence>& pts);

/// Splits P (seed 000 eqs. 3–6). Flips the sign of P so det(P₃ₓ₃) > 0. Throws if P₃ₓ₃ is singular.
KrcDecomposition decompose_projection_matrix(const ProjectionMatrix& P);

/// Maps K, R, C onto rangecal's camera model for the given sensor (see the header comment).
Camera camera_from_krc(const KrcDecomposition& krc, const SensorGeometry& sensor);

/// The full initialiser: checks, RANSAC (if enabled), refit on inliers, decomposition.
/// Throws rangecal::Error(calibration) naming the cause: fewer than 6 points, NaN/inf, collinear or
/// coplanar points, a singular system, too few RANSAC inliers, points behind the camera.
DltResult dlt_calibrate(const std::vector<PointCorrespondence>& pts, const SensorGeometry& sensor,
                        const DltOptions& options = {});

}  // namespace rangecal
