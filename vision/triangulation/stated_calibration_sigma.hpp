#pragma once
// The uncertainty a user states for a calibration made elsewhere (an OpenCV YAML, a DLT-11;
// docs/trajectory.md "Imported calibrations"), as the parameter covariance the trajectory propagates
// (docs/conventions.md's parameters, vision/camera/camera_parameters.hpp):
//   f        σ_f = focal_px · dy            (mm; the focal length in pixels, fx and fy together)
//   u0, v0   principal_point_px each        (px)
//   wx wy wz rotation_mrad · 1e-3 each      (rad; an isotropic σ, the same in any axes)
//   CE CN CU position_m each                (m; the camera centre, site ENU)
// independent of each other: a calibration stated by its parts. What no parameter carries — a lens
// model's residual, a conversion's fit — is `image_px`, a pixel σ the trajectory adds to every view of
// the camera (vision/triangulation/target_trajectory.hpp, TrajectoryCamera::model_sigma_px).
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

struct StatedCalibrationSigma {
  double focal_px = 0;            ///< 1σ of the focal length (px)
  double principal_point_px = 0;  ///< 1σ of u0 and of v0 (px)
  double position_m = 0;          ///< 1σ of each coordinate of the camera centre (m)
  double rotation_mrad = 0;       ///< 1σ of a rotation about each axis (mrad)
  double image_px = 0;            ///< 1σ per image axis of the model's error at the pixel (px)
};

/// The diagonal covariance over f, u0, v0, wx, wy, wz, CE, CN, CU of `camera` (its pitch dy_mm > 0)
/// for `sigma`. Parameters whose σ is 0 are left out (taken as exact); an all-zero σ gives an empty
/// covariance. Throws rangecal::Error (input) naming the field when a σ is negative or not finite.
CameraCovariance stated_camera_covariance(const Camera& camera, const StatedCalibrationSigma& sigma);

}  // namespace rangecal
