#pragma once
// Tsai's two-step calibration for non-coplanar points with unknown scale factor sx
// (Tsai 1987, §III.B; seed 002 eqs. 11–13 as corrected in seeds/NOTES.md).
//
// Model: docs/conventions.md / vision/camera/camera_model.hpp with radial k1 only (distorted → undistorted):
//   Xc = R·Xw + T;  xu = f·Xc/Zc, yu = f·Yc/Zc;  xu = xd(1 + k1 rd²), yu = yd(1 + k1 rd²);
//   u = u0 + sx·xd/dx,  v = v0 + yd/dy.
// The principal point (u0, v0) is not estimated: it is given (default: the image centre,
// ((width−1)/2, (height−1)/2) in docs/conventions.md pixels).
//
// Step 1 (linear, immune to radial distortion — the radial alignment constraint, eq. 11):
//   with Xd' = (u−u0)·dx = sx·xd and Yd = (v−v0)·dy, one row per point (eq. 12):
//   [Xw·Yd, Yw·Yd, Zw·Yd, Yd, −Xw·Xd', −Yw·Xd', −Zw·Xd'] · L = Xd',
//   L = [sx·r1/Ty, sx·r2/Ty, sx·r3/Ty, sx·Tx/Ty, r4/Ty, r5/Ty, r6/Ty];
//   |Ty| = 1/‖L5..7‖, sign of Ty from the point farthest from the image centre, sx = ‖L1..3‖·|Ty|,
//   rows 1–2 of R from L, row 3 = row1 × row2, then the nearest rotation (SVD).
//   Frames (Tsai 1987 §III.B: the origin must lie in view and away from the v = v0 line, since eq. 12
//   divides by Ty and the recovery pivots R about the origin): the user's world origin may lie
//   anywhere — behind the camera, at it, far off its axis — so eq. 12 is solved with the world
//   coordinates taken about the point with the largest |yc| (in view, as far from v = v0 as the
//   points allow; yc from the homogeneous form of eq. 11, which does not divide by Ty), its solution
//   is re-expressed about the centroid of the points (in view), R, Tx, Ty are recovered there
//   (scaled by ‖r4..r6‖ = 1) and mapped back exactly: with Xw = Xa + a, T = Ta − R·a and the camera
//   centre C = Ca + a. The result does not depend on the user's frame (a rotation of it is a linear
//   re-parametrisation of L). ty_ratio = |Ty| / max_i |yc_i| reports how weak the user's own frame
//   was. Step 2 needs no translation: its residuals depend on the camera coordinates Xc alone.
// Step 2: f and Tz linearly ignoring distortion (eq. 15; on the f–distance ridge of a narrow field,
//   where that solve is ill-conditioned, from the lens's nominal f or the depth profile of eq. 13
//   instead: tsai_f_tz_start), then (f, Tz, k1) by Levenberg–Marquardt on the eq. 13 residuals
//   (undistorted sensor mm):
//   g = [xd(1+k1 r²) − f·Xc/Zc,  yd(1+k1 r²) − f·Yc/Zc],  r² = xd² + yd²,  xd = Xd'/sx.
//   If the linear f comes out negative the Ty sign was wrong: rows 1–2 of R, Tx, Ty and f are negated
//   (a 180° turn about the optical axis, R stays a proper rotation).
//
// Units: world points in any length unit (T comes back in the same unit); f in mm; k1 in mm⁻².
// Errors: rangecal::Error kind calibration (exit 4) naming the cause — fewer than 7 points (or
// 8 for step 2 with k1), non-finite input, all points on one line, coplanar points (also those
// coplanar with the camera), a singular system, no focal length fitting the points in front of the
// camera. The world origin may lie anywhere, also at the camera centre.
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "vision/calibration/point_correspondence.hpp"
#include "vision/camera/camera_model.hpp"

namespace rangecal {

/// Sensor and principal point that Tsai's method takes as known.
struct TsaiSensor {
  int width_px = 0;
  int height_px = 0;
  double dx_mm = 0;  ///< horizontal pixel pitch (mm) — Tsai's dpx = dx·Ncx/Nfx
  double dy_mm = 0;  ///< vertical pixel pitch (mm)
  /// Principal point (px). NaN → image centre ((width−1)/2, (height−1)/2).
  double u0_px = std::numeric_limits<double>::quiet_NaN();
  double v0_px = std::numeric_limits<double>::quiet_NaN();
};

/// Result of step 1 (reused by tsai_sassa, which searches f, Tz, k1 from here).
struct TsaiStep1 {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< world → camera, proper rotation (SVD-orthonormalised)
  double Tx = 0;                                    ///< world units
  double Ty = 0;                                    ///< world units, sign fixed
  double sx = 1;                                    ///< scale factor
  double u0_px = 0, v0_px = 0;                      ///< the principal point used
  /// RMS of the eq. 12 linear system residual (mm, in Xd' units).
  double linear_rms_mm = 0;
  /// Largest deviation of the raw rows 1–2 from orthonormality before the SVD projection
  /// (max |RᵣRᵣᵀ − I| over the 2×2 block) — a diagnostic of noise/model mismatch.
  double orthogonality_error = 0;
  /// |Ty| / max_i |yc_i| in the given world frame, from the homogeneous form of eq. 11 (which does
  /// not divide by Ty): 0 with the world origin on the camera's XZ plane. A diagnostic only.
  double ty_ratio = 1;
  /// Where eq. 12 was solved and R, Tx, Ty recovered (world coordinates taken about these points):
  /// the point with the largest |yc| and the centroid of the world points; both zero in the
  /// willson_rpy mode (the user's frame, as the reference program). R, Tx, Ty above are always those
  /// of the given frame; linear_rms_mm and orthogonality_error are those of the solve.
  Eigen::Vector3d eq12_origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d pose_origin = Eigen::Vector3d::Zero();
};

/// Where step 2 starts (f, Tz) and why there.
enum class TsaiStartSource {
  linear,                ///< Tsai 1987 eq. 15 (distortion ignored), as published
  nominal_focal_length,  ///< eq. 15 ill-conditioned: the lens's nominal f, Tz best for it
  depth_profile,         ///< eq. 15 ill-conditioned, no lens given: f, Tz minimising eq. 13 (k1 = 0)
};

struct TsaiStart {
  double f_mm = 0;  ///< start of step 2
  double Tz = 0;    ///< world units
  TsaiStartSource source = TsaiStartSource::linear;
  double f_linear_mm = 0;  ///< |f| of eq. 15 (0 when singular)
  double Tz_linear = 0;    ///< Tz of eq. 15
  /// Standard error of eq. 15's f relative to |f| (from its residual): above 0.1 the solve is on the
  /// f–distance ridge of a narrow field and not used (infinite when singular).
  double f_linear_rel_sigma = std::numeric_limits<double>::infinity();
};

/// Step 2 result plus diagnostics.
struct TsaiResult {
  Camera camera;             ///< f, sx, u0, v0, k1, R, T (T in world units)
  TsaiStep1 step1;           ///< the linear step
  double f_linear_mm = 0;    ///< f from the linear f/Tz solve (distortion ignored; 0 when singular)
  double Tz_linear = 0;      ///< Tz from that solve (world units)
  TsaiStart start;           ///< where step 2's LM started (the linear solve, or not: see TsaiStart)
  double rms_sensor_mm = 0;  ///< RMS of the eq. 13 residual components at the solution (mm)
  double rms_px = 0;         ///< RMS reprojection error (pixel distance per point) at the solution
  int iterations = 0;        ///< Levenberg–Marquardt iterations of step 2
  bool converged = false;    ///< LM met its step/gradient tolerance
  /// Empty, or what step 2 fell back to because its solution did not project every point.
  std::string fallback;
};

/// How step 1's rows r1..r3, r4..r6 (orthonormal only up to noise) become a rotation.
enum class TsaiOrthonormalisation {
  svd,          ///< Frobenius-nearest proper rotation of [row1; row2; row1 × row2] (default)
  willson_rpy,  ///< as Willson's reference program (ncc_compute_better_R): roll-pitch-yaw angles
                ///< Rz = atan2(r4, r1), Ry = atan2(−r7, r1·cos Rz + r4·sin Rz),
                ///< Rx = atan2(r3·sin Rz − r6·cos Rz, r5·cos Rz − r2·sin Rz), R = Rz·Ry·Rx rebuilt;
                ///< also Tx = L4·Ty without Tsai's 1/sx, and step 1 in the user's world frame,
                ///< as that program does — only for reproducing its published results
};

struct TsaiOptions {
  bool estimate_k1 = true;  ///< false: k1 = 0, only f and Tz are refined
  /// The lens's nominal focal length (mm; ≤ 0: unknown): step 2 starts there when eq. 15 is
  /// ill-conditioned (tsai_f_tz_start).
  double nominal_f_mm = 0;
  int max_iterations = 100;
  TsaiOrthonormalisation orthonormalisation = TsaiOrthonormalisation::svd;
};

/// Step 1 only (R, Tx, Ty in the given world frame, whichever frames it solved in). Throws
/// rangecal::Error(calibration) on degenerate input.
TsaiStep1 tsai_step1(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                     TsaiOrthonormalisation orthonormalisation = TsaiOrthonormalisation::svd);

/// Linear f and Tz given step 1 (distortion ignored; Tsai 1987 eq. 15, both image axes used).
/// Handles the f < 0 case by flipping the Ty sign in `step1` (see above). Returns {f_mm, Tz}.
std::pair<double, double> tsai_linear_f_tz(const std::vector<PointCorrespondence>& pts,
                                           const TsaiSensor& sensor, TsaiStep1* step1);

/// Step 2's start. Eq. 15 as tsai_linear_f_tz when it is well-conditioned (relative standard error
/// of f ≤ 0.1) and puts every point in front of the camera. Otherwise — the f–distance ridge of a
/// narrow field, where the linear f, Tz scatter far along the ridge and may put points behind the
/// camera — the depth profile of eq. 13 without distortion (f in closed form for each Tz, Tz searched
/// over the whole range in front of the camera) gives the sign of f (fixing Ty's as above), and the
/// start is f = nominal_f_mm with its best Tz when the lens is known, else the profile's minimum.
/// Throws only when no focal length fits at all.
TsaiStart tsai_f_tz_start(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                          TsaiStep1* step1, double nominal_f_mm = 0);

/// Eq. 13 residuals (sensor mm, 2 per point: x then y) for given step 1 and (f, Tz, k1). For searches
/// (tsai_sassa) that need the same objective; returns the sum of squares.
double tsai_eq13_cost(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                      const TsaiStep1& step1, double f_mm, double Tz, double k1,
                      Eigen::VectorXd* residuals = nullptr);

/// Builds the rangecal Camera from step 1 and (f, Tz, k1).
Camera tsai_camera(const TsaiSensor& sensor, const TsaiStep1& step1, double f_mm, double Tz, double k1);

/// Step 2 from a given step 1: f, Tz from tsai_f_tz_start, then LM over f, Tz, k1 on eq. 13.
TsaiResult tsai_step2(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor, TsaiStep1 step1,
                      const TsaiOptions& options = {});

/// Full refinement (Willson's "nccal_fo" stage, beyond Tsai's two steps): all of f, sx, u0, v0, k1,
/// R, T by Ceres Levenberg–Marquardt on the same eq. 13 residuals (undistorted sensor mm), with the
/// principal point free. Starts from `start` (e.g. tsai_calibrate's camera). With a narrow field of
/// view u0, v0 trade against R and are poorly determined (docs/optimisation.md); use on wide views / rigs.
TsaiResult tsai_full_refinement(const std::vector<PointCorrespondence>& pts, const Camera& start,
                                int max_iterations = 200);

/// The whole two-step method.
TsaiResult tsai_calibrate(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                          const TsaiOptions& options = {});

}  // namespace rangecal
