#pragma once
// Export of a rangecal camera to the DLT tools of biomechanics (DLTdv, Argus, easyWand;
// docs/outputs.md "DLT export"): 11 DLT coefficients for the distortion-free part and a pinhole
// undistortion profile for the rest.
//
// DLT-11 (Abdel-Aziz & Karara 1971), world point (X, Y, Z) = site ENU (m):
//   x = (L1 X + L2 Y + L3 Z + L4) / (L9 X + L10 Y + L11 Z + 1)
//   y = (L5 X + L6 Y + L7 Z + L8) / (L9 X + L10 Y + L11 Z + 1)
// in the tools' pixel frame: origin at the bottom-left corner of the image, x right, y up,
// continuous (Argus' clicker takes pyglet window coordinates, whose origin is the image's
// bottom-left corner; its tools.dlt_inverse documents "origin at the bottom left"). From
// rangecal's pixels (centre of the top-left pixel (0, 0), v down, W × H image):
//   x = u + 0.5,  y = H − 0.5 − v.
// The coefficients are exact: L = P / P₃₄ for P = K·A·F·[R | T], F = diag(1, −1, 1) turning
// rangecal's y-down camera axes to the tools' y-up ones, K and A from the profile fit below.
//
// Undistortion profile (Argus pinhole model, the one Argus and DLTdv apply to clicked points
// before the DLT): one f, principal point (cx, cy) in the same frame, and OpenCV's k1 k2 t1 t2 k3
// (t1, t2 = OpenCV's p1, p2); Argus undistorts with cv2.undistortPoints(pts, K, [k1 k2 t1 t2 k3],
// P = K), K = [f 0 cx; 0 f cy; 0 0 1], default iterations (5). The profile is fitted
// (vision/camera/opencv_distortion_fit.hpp) to rangecal's distortion over the image in both
// directions, with a 2 × 2 A = [a b; 0 1] on the normalised ray absorbed into the DLT (it takes up
// sx ≠ 1, which a one-f profile cannot).
#include <array>
#include <string>
#include <vector>

#include "vision/camera/camera_model.hpp"

namespace rangecal {

struct DltCamera {
  std::string id;
  int width_px = 0, height_px = 0;
  std::array<double, 11> L{};  ///< L1 … L11, tools' pixel frame, world site ENU (m)
  /// The Argus pinhole profile: f, cx, cy (px, tools' frame), k1 k2 t1 t2 k3 (OpenCV's units).
  double f_px = 0, cx_px = 0, cy_px = 0;
  std::array<double, 5> k{};
  /// The DLT alone against rangecal's projection (distortion ignored), over the image (px).
  double dlt_only_rms_px = 0, dlt_only_max_px = 0;
  /// DLT + profile against rangecal, in the profile's forward direction (distorting the DLT's
  /// pixel) and in the tools' direction (cv::undistortPoints of rangecal's pixel, 5 iterations,
  /// against the DLT's pixel), over the image (px).
  double profile_max_px = 0, profile_rms_px = 0;
  double undistort_max_px = 0, undistort_rms_px = 0;
  int points = 0;  ///< evaluation samples
};

/// rangecal pixel → the tools' pixel frame of an image `height_px` high (see the header).
Eigen::Vector2d to_dlt_pixel(const Eigen::Vector2d& uv, int height_px);
/// The tools' pixel frame → rangecal pixel.
Eigen::Vector2d from_dlt_pixel(const Eigen::Vector2d& xy, int height_px);

/// The DLT-11 coefficients and Argus profile of `cam` (image size, f, pitch and sx must be valid,
/// else rangecal::Error kind calibration; also when the world origin lies in the camera's principal
/// plane, where L cannot be normalised by P₃₄).
DltCamera dlt_camera(const Camera& cam);

/// The DLTdv/Argus coefficient file: 11 lines, one comma-separated column per camera (in order),
/// no header. Deterministic, 15 significant digits.
std::string dlt_coefficients_csv(const std::vector<DltCamera>& cameras);

/// The Argus camera profile (.txt): one line per camera, space separated: camera number (1, 2, …
/// in order), f, image width, image height, cx, cy, aspect ratio (1), k1, k2, t1, t2, k3.
std::string argus_profile_txt(const std::vector<DltCamera>& cameras);

}  // namespace rangecal
