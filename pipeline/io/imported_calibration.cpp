#include "pipeline/io/imported_calibration.hpp"

#include <cmath>

#include "config/error.hpp"
#include "vision/calibration/dlt_camera_import.hpp"
#include "vision/camera/opencv_camera_import.hpp"
#include "vision/camera/sensor_geometry.hpp"

namespace rangecal {
namespace {

// The model's conversion failed: the file holds no camera rangecal can take — an input error of
// that file, not a failed calibration of the mission.
template <typename F>
ImportedCamera converted(const std::string& file, const std::string& field, F&& convert) {
  try {
    return convert();
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::calibration) throw;
    throw_input_error(file, 0, field, e.reason());
  }
}

}  // namespace

ImportedCalibration read_imported_calibration(const ImportedCameraConfig& cfg) {
  const double dx = cfg.sensor.pixel_size_um[0] * 1e-3, dy = cfg.sensor.pixel_size_um[1] * 1e-3;
  ImportedCalibration out;
  ImportedCamera cam;
  if (!cfg.opencv_yml.empty()) {
    out.format = "opencv_yml";
    out.file = cfg.opencv_yml;
    const OpenCvCamera oc = read_opencv_camera_yml(cfg.opencv_yml);
    if (oc.image_width != cfg.sensor.width_px || oc.image_height != cfg.sensor.height_px)
      throw_input_error(
          cfg.opencv_yml, 0, oc.image_width != cfg.sensor.width_px ? "image_width" : "image_height",
          "the file's image is " + std::to_string(oc.image_width) + " × " + std::to_string(oc.image_height) +
              " px and camera " + cfg.id + "'s sensor " + std::to_string(cfg.sensor.width_px) + " × " +
              std::to_string(cfg.sensor.height_px));
    cam = converted(cfg.opencv_yml, "", [&] { return camera_from_opencv(oc, dx, dy); });
  } else {
    out.format = "dlt";
    out.file = cfg.dlt;
    const std::array<double, 11> L = read_dlt_coefficients_csv(cfg.dlt, cfg.dlt_column);
    cam = converted(cfg.dlt, "column " + std::to_string(cfg.dlt_column), [&] {
      return camera_from_dlt(L, SensorGeometry{cfg.sensor.width_px, cfg.sensor.height_px, dx, dy});
    });
  }
  out.camera = cam.camera;
  out.camera.id = cfg.id;
  out.fit_rms_px = cam.fit_rms_px;
  out.fit_max_px = cam.fit_max_px;
  out.model_sigma_px = std::hypot(cfg.sigma.image_px, cam.fit_rms_px);
  out.covariance = stated_camera_covariance(out.camera, cfg.sigma);
  return out;
}

}  // namespace rangecal
