#pragma once
// How far a camera's exports reproduce it (docs/outputs.md "Exports"): the OpenCV model
// (vision/camera/opencv_camera_export.hpp) and the DLT-11 + Argus profile
// (vision/camera/dlt_export.hpp) are fits of rangecal's camera, not conversions, and on a wide or
// strongly distorted lens a fit can miss it by pixels. Beyond what their users can ignore a warning;
// beyond kUnusableExportPx the export is refused — not written, the run degraded — since a file that
// cannot stand for its camera must not look as if it could.
#include <string>
#include <vector>

#include "vision/camera/dlt_export.hpp"
#include "vision/camera/opencv_camera_export.hpp"

namespace rangecal {

/// An export that reproduces its camera only this far (px, at the worst of its check points,
/// either direction) cannot stand for it.
inline constexpr double kUnusableExportPx = 1.0;
/// Below these the exports' error is no warning: OpenCV's model (px), the DLT + profile (px).
inline constexpr double kOpenCvWarnPx = 0.01;
inline constexpr double kDltWarnPx = 0.05;

struct ExportCheck {
  double opencv_fit_max_px = 0, opencv_undistort_max_px = 0;
  double dlt_only_rms_px = 0, dlt_only_max_px = 0;
  double dlt_profile_max_px = 0;      ///< the larger of the profile's and its undistortion's
  bool opencv_refused = false;        ///< camera_opencv.yml is not written
  bool dlt_refused = false;           ///< dlt_coefficients.csv and argus_profile.txt are not written
  std::vector<std::string> refused;   ///< per refused export: "file(s): why"
  std::vector<std::string> warnings;  ///< the exports' error where it is worth a warning, and the refusals
};

ExportCheck check_exports(const OpenCvCamera& opencv, const DltCamera& dlt);

}  // namespace rangecal
