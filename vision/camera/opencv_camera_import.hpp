#pragma once
// Import of an OpenCV camera (cv::calibrateCamera's K, distortion, rvec, tvec) into rangecal's
// model (docs/conventions.md), the inverse of vision/camera/opencv_camera_export.hpp — e.g. to intersect with
// a camera calibrated elsewhere, or to compare a lab calibration with the range's.
//
// Intrinsics map exactly, given the sensor's pixel pitch (OpenCV has none):
//   v = cy + fy·y''  ↔  v = v0 + yd/dy            ⇒ f = fy·dy, v0 = cy
//   u = cx + fx·x''  ↔  u = u0 + sx·xd/dx         ⇒ sx = fx·dx/f, u0 = cx
// The distortions run in opposite directions (OpenCV: undistorted → distorted normalised;
// rangecal: distorted → undistorted sensor mm, seed 000 eq. 7), so rangecal's k1 k2 k3 p1 p2 are
// fitted: on a grid of pixels, OpenCV's exact inverse (cv::undistortPoints, iterated to 1e-14)
// gives the undistorted point xu = f·x', and Δ = xu − xd is linear in the coefficients — one
// linear least-squares solve (columns scaled). The fit error is then measured on a denser, offset
// grid as the pixel distance between rangecal's projection of OpenCV's ray and the pixel itself.
#include <Eigen/Core>

#include "vision/camera/camera_model.hpp"
#include "vision/camera/imported_camera.hpp"
#include "vision/camera/opencv_camera_export.hpp"

namespace rangecal {

/// Converts `oc` (image size set; 5 or 8 distortion coefficients) with the sensor's pixel pitch
/// dx_mm × dy_mm. Throws rangecal::Error (calibration) when K is not a pinhole matrix with
/// positive focal lengths, the pitch is not positive, or the distortion cannot be inverted over
/// the image (OpenCV's model folds back inside it).
ImportedCamera camera_from_opencv(const OpenCvCamera& oc, double dx_mm, double dy_mm);

}  // namespace rangecal
