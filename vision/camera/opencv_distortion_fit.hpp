#pragma once
// OpenCV's point-distortion model fitted to a rangecal camera, in both of the directions OpenCV
// evaluates it: cv::projectPoints (normalised point → pixel, closed form) and cv::undistortPoints
// with its default settings (pixel → normalised point by a fixed number of fixed-point
// iterations, 5 by default; OpenCV calib3d docs, "Default version of undistortPoints does 5
// iterations"). The camera_opencv.yml export and the Argus/DLTdv undistortion profile are both
// this fit, in different pixel frames.
//
// The model (OpenCV calib3d "Detailed description"; coefficients in OpenCV's order
// k1 k2 p1 p2 k3 [k4 k5 k6 [s1 s2 s3 s4]]):
//   r² = x² + y²,  x'' = x·(1 + k1 r² + k2 r⁴ + k3 r⁶)/(1 + k4 r² + k5 r⁴ + k6 r⁶)
//                        + 2 p1 x y + p2 (r² + 2x²) + s1 r² + s2 r⁴
//                  y'' = y·(same ratio) + p1 (r² + 2y²) + 2 p2 x y + s3 r² + s4 r⁴
//   pixel = (fx·x'' + cx, fy·y'' + cy)
// cv::undistortPoints inverts it by x ← (x''₀ − Δ(x))·(1 + k4 r² …)/(1 + k1 r² …), started at
// x = x''₀; with 5 iterations its error is that of a fixed-point iteration whose contraction is
// set by the lens (≈ 0.19 per step for seed 002's 7 % corner distortion), so the fit minimises
// the error of both directions together: see fit_opencv_distortion.
#include <Eigen/Core>
#include <vector>

#include "vision/camera/camera_model.hpp"

namespace rangecal {

/// OpenCV's camera matrix and distortion coefficients (pixels; coefficients in OpenCV's order and
/// units: normalised coordinates, k1 per unit r², …). 5, 8 or 12 coefficients.
struct OpenCvDistortionModel {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<double> coefficients = std::vector<double>(5, 0.0);
};

/// cv::projectPoints' distortion: normalised undistorted point (x, y) = (Xc/Zc, Yc/Zc) → pixel.
Eigen::Vector2d opencv_distort(const OpenCvDistortionModel& m, const Eigen::Vector2d& x);

/// cv::undistortPoints' algorithm (OpenCV 4 cvUndistortPointsInternal, without R and P):
/// `iterations` fixed-point steps from the distorted normalised point, stopping early (at the
/// distorted point) where the radial ratio turns negative. Pixel → normalised point.
Eigen::Vector2d opencv_undistort_point(const OpenCvDistortionModel& m, const Eigen::Vector2d& pixel,
                                       int iterations = 5);

/// One point of the mapping to fit: a pixel in the target frame and the normalised undistorted
/// point (the camera ray's x/z, y/z in the target frame's axes) OpenCV must map it to.
struct DistortionSample {
  Eigen::Vector2d normalised;
  Eigen::Vector2d pixel;
};

/// `nu` × `nv` pixels spread evenly over the image area [−0.5, W − 0.5] × [−0.5, H − 0.5] of
/// `cam` (rangecal pixels: centre of the top-left pixel (0, 0), v down), `offset` grid steps in
/// (0 or 0.5; clamped to the edge), each with its exact normalised ray (x/z, y/z in rangecal's
/// camera axes: x right, y down) from rangecal's closed-form undistortion.
std::vector<DistortionSample> image_grid_samples(const Camera& cam, int nu, int nv, double offset);

struct OpenCvFitOptions {
  /// Coefficient layouts to try, in order of preference; the first whose error (the larger of
  /// the two directions' maxima) is within tolerance_px is kept, else the one with the least.
  std::vector<int> layouts = {5, 8, 12};
  double tolerance_px = 0.01;
  /// One focal length (fx = fy), as tools with a single f in their profile need.
  bool equal_focal = false;
  /// Fit the model to A·normalised with A = [a b; 0 1] estimated too (for exports whose linear
  /// part absorbs A, e.g. a DLT matrix): takes up sx ≠ 1 and skew-like terms an equal-focal,
  /// radially symmetric model cannot.
  bool free_affine = false;
  /// Iterations of the cv::undistortPoints emulation the fit and its report use.
  int undistort_iterations = 5;
  /// Weight of the cv::undistortPoints residuals against the cv::projectPoints ones (0: fit the
  /// projection alone, exact for an iteration count that converges).
  double undistort_weight = 1.0;
  /// Rounds of Lawson's reweighting after the least-squares fit, towards the least maximum
  /// error over the samples (the tolerances are maxima); the best round is kept.
  int minimax_rounds = 0;
};

struct OpenCvFit {
  OpenCvDistortionModel model;
  Eigen::Matrix2d affine = Eigen::Matrix2d::Identity();  ///< A (identity unless free_affine)
  /// cv::projectPoints direction: |pixel(A·x) − pixel| over the evaluation samples (px).
  double project_max_px = 0, project_rms_px = 0;
  /// cv::undistortPoints direction: |undistort(pixel) − A·x| scaled to pixels by fx, fy (px).
  double undistort_max_px = 0, undistort_rms_px = 0;
  int points = 0;  ///< evaluation samples
};

/// Fits `initial` (its camera matrix and any coefficients as a start) to `fit_samples` by least
/// squares (Ceres LM) on the pixel residuals of both directions with equal weight, the
/// coefficients conditioned by fitting them in coordinates scaled to unit radius at the farthest
/// sample; reports the errors on `eval_samples`. Deterministic.
OpenCvFit fit_opencv_distortion(const std::vector<DistortionSample>& fit_samples,
                                const std::vector<DistortionSample>& eval_samples,
                                const OpenCvDistortionModel& initial, const OpenCvFitOptions& options);

}  // namespace rangecal
