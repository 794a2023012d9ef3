#pragma once
// Export of a rangecal camera to OpenCV's camera model (docs/outputs.md `camera_opencv.yml`).
//
// The two models run in opposite directions: rangecal's distortion maps distorted → undistorted
// sensor millimetres (Tsai; seed 000 eq. 7), OpenCV's maps undistorted → distorted normalised
// coordinates:
//   x' = Xc/Zc, y' = Yc/Zc, r² = x'² + y'²
//   x'' = x'·(1 + k1 r² + k2 r⁴ + k3 r⁶)/(1 + k4 r² + k5 r⁴ + k6 r⁶) + 2 p1 x'y' + p2 (r² + 2x'²)
//   y'' = y'·(same ratio) + p1 (r² + 2y'²) + 2 p2 x'y'
//   u = fx·x'' + cx,  v = fy·y'' + cy
// There is no closed-form conversion, so the OpenCV parameters (fx, fy, cx, cy and 5, 8 or 12
// coefficients) are fitted (vision/camera/opencv_distortion_fit.hpp) to rangecal's exact
// pixel ↔ ray mapping on a dense grid over the image, in both directions OpenCV evaluates them:
// cv::projectPoints and cv::undistortPoints with its default 5 iterations. The errors of both
// are measured on a denser, offset grid; the fewest coefficients that keep both within the
// tolerance are kept (else the layout with the least error).
// The pose needs no fit: both models use Xc = R·Xw + T with x right, y down, z forward.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "vision/camera/camera_model.hpp"
#include "vision/camera/opencv_distortion_fit.hpp"

namespace rangecal {

struct OpenCvCamera {
  int image_width = 0;
  int image_height = 0;
  Eigen::Matrix3d camera_matrix = Eigen::Matrix3d::Identity();  ///< [fx 0 cx; 0 fy cy; 0 0 1] (px)
  /// OpenCV order: k1, k2, p1, p2, k3 (5) or k1, k2, p1, p2, k3, k4, k5, k6 (8, rational model).
  std::vector<double> distortion_coefficients;
  Eigen::Vector3d rvec = Eigen::Vector3d::Zero();  ///< Rodrigues vector of R (world ENU → camera)
  Eigen::Vector3d tvec = Eigen::Vector3d::Zero();  ///< T (m)
  double fit_max_px = 0;  ///< cv::projectPoints: max |OpenCV − rangecal| over the evaluation grid (px)
  double fit_rms_px = 0;  ///< RMS of the same (px)
  int fit_points = 0;     ///< number of evaluation grid points
  /// cv::undistortPoints with `undistort_iterations` (5, its default): max and RMS over the same
  /// grid of |OpenCV's normalised point − rangecal's ray|, scaled to pixels by fx, fy.
  double undistort_max_px = 0;
  double undistort_rms_px = 0;
  int undistort_iterations = 5;
};

/// Fits OpenCV's model to `cam` over its image (width_px × height_px must be set). Uses the
/// rational (and then thin-prism) layout only when the 5-coefficient fit's error in either
/// direction exceeds `tolerance_px`. The result reports both errors; a caller that needs the
/// tolerance checks fit_max_px and undistort_max_px itself.
OpenCvCamera fit_opencv_camera(const Camera& cam, double tolerance_px = 0.01);

/// OpenCV's forward projection of a world point (metres) with `oc`, evaluated exactly as
/// cv::projectPoints does (no behind-camera check). For tests and diagnostics.
Eigen::Vector2d project_opencv(const OpenCvCamera& oc, const Eigen::Vector3d& Xw);

/// `oc`'s camera matrix and distortion coefficients as the fit's model type.
OpenCvDistortionModel opencv_distortion_model(const OpenCvCamera& oc);

/// The camera_opencv.yml text written by cv::FileStorage (YAML): image_width, image_height,
/// camera_matrix (3×3), distortion_coefficients (1×5 or 1×8), rvec (3×1), tvec (3×1), and the
/// fit error keys fit_max_error_px, fit_rms_error_px, fit_points (cv::projectPoints) and
/// undistort_points_max_error_px, undistort_points_rms_error_px, undistort_points_iterations
/// (cv::undistortPoints). Deterministic.
std::string opencv_camera_yml_text(const OpenCvCamera& oc);

/// Writes camera_opencv.yml atomically.
void write_opencv_camera_yml(const std::string& path, const OpenCvCamera& oc);

/// Reads a camera_opencv.yml (as written above, or any OpenCV YAML file with these keys) with
/// rangecal's own reader of OpenCV's YAML (config/opencv_yaml.hpp), never cv::FileStorage, whose
/// parser can hang on a damaged file. Throws rangecal::Error (input) naming the file, line and key
/// when a key is missing or malformed.
OpenCvCamera read_opencv_camera_yml(const std::string& path);

}  // namespace rangecal
