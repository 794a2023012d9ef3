#pragma once
// A camera converted into rangecal's model from another tool's (an OpenCV camera:
// vision/camera/opencv_camera_import.hpp; a DLT-11: vision/calibration/dlt_camera_import.hpp), with
// how far the conversion reproduces it over the image.
#include "vision/camera/camera_model.hpp"

namespace rangecal {

struct ImportedCamera {
  Camera camera;
  double fit_max_px = 0;  ///< max reprojection difference over the evaluation grid (px)
  double fit_rms_px = 0;  ///< RMS of the same (px)
  int fit_points = 0;     ///< evaluation grid points
};

}  // namespace rangecal
