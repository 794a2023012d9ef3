#pragma once
// A camera calibrated elsewhere (trajectory.imported_cameras[i]; docs/trajectory.md "Imported
// calibrations") read from its file — an OpenCV camera YAML (vision/camera/opencv_camera_import.hpp)
// or a DLT-11 column (vision/calibration/dlt_camera_import.hpp) — into rangecal's model, with the
// covariance of the σ its user states (vision/triangulation/stated_calibration_sigma.hpp); or
// another mission's calibration.json, with its own covariance.
#include <string>

#include "pipeline/mission/mission_config.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

struct ImportedCalibration {
  Camera camera;                ///< id set
  CameraCovariance covariance;  ///< the stated σ's (empty when every σ is 0)
  /// The error at the pixel no parameter carries: the stated image_px and the conversion's fit rms
  /// in quadrature (px per axis).
  double model_sigma_px = 0;
  double fit_rms_px = 0, fit_max_px = 0;  ///< the conversion into rangecal's model, over the image (px)
  std::string format;                     ///< "opencv_yml", "dlt" or "rangecal_json"
  std::string file;
};

/// Reads `cfg`'s calibration file; `site` is the mission's ENU origin, which a calibration.json's
/// world frame must be. Throws rangecal::Error (input) naming the file (and line, key or column)
/// when it is missing or malformed, when its image size is not the sensor's, when a calibration.json
/// has another site origin or no usable covariance,
/// or when its content is no camera rangecal's model can take (a K with skew, a distortion that
/// folds back over the image, DLT coefficients without a camera centre or whose principal point lies
/// off the image).
ImportedCalibration read_imported_calibration(const ImportedCameraConfig& cfg, const GeodeticOrigin& site);

}  // namespace rangecal
