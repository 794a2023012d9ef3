#include "pipeline/io/imported_calibration.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <utility>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "vision/calibration/dlt_camera_import.hpp"
#include "vision/camera/opencv_camera_import.hpp"
#include "vision/camera/sensor_geometry.hpp"
#include "vision/triangulation/calibration_covariance.hpp"

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

// A covariance that leaves out the focal length, the principal point, the attitude or the position
// would import those as exact, and one not positive semi-definite states no uncertainty at all.
void require_whole_covariance(const CameraCovariance& c, const std::string& file) {
  using P = CameraParameter;
  const auto has = [&](P p) {
    return std::find(c.parameters.begin(), c.parameters.end(), p) != c.parameters.end();
  };
  std::string missing;
  for (const auto& [p, name] : {std::pair<P, const char*>{P::f, "f"},
                                {P::u0, "u0"},
                                {P::v0, "v0"},
                                {P::wx, "wx"},
                                {P::wy, "wy"},
                                {P::wz, "wz"}})
    if (!has(p)) missing += std::string(missing.empty() ? "" : ", ") + name;
  if (!(has(P::CE) && has(P::CN) && has(P::CU)) && !(has(P::Tx) && has(P::Ty) && has(P::Tz)))
    missing += std::string(missing.empty() ? "" : ", ") + "the position (CE CN CU or Tx Ty Tz)";
  if (!missing.empty())
    throw_input_error(
        file, 0, "covariance",
        "leaves out " + missing + ": those would be imported as exact; calibrate with them free");
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(c.covariance);
  if (eig.info() != Eigen::Success ||
      eig.eigenvalues().minCoeff() < -1e-12 * std::max(1e-300, eig.eigenvalues().maxCoeff()))
    throw_input_error(file, 0, "covariance", "is not positive semi-definite: it states no uncertainty");
}

// Another mission's calibration.json: its camera and its covariance as they stand, when its world
// frame is this site's ENU (an origin equal to 1e-9° and 1 mm: the same survey's site).
ImportedCalibration from_calibration_json(const ImportedCameraConfig& cfg, const GeodeticOrigin& site) {
  ImportedCalibration out;
  out.format = "rangecal_json";
  out.file = cfg.rangecal_json;
  const CalibrationResult r = read_calibration_json(cfg.rangecal_json);
  const GeodeticOrigin& o = require_site_origin(r, cfg.rangecal_json);
  if (std::abs(o.lat_deg - site.lat_deg) > 1e-9 || std::abs(o.lon_deg - site.lon_deg) > 1e-9 ||
      std::abs(o.h_m - site.h_m) > 1e-3)
    throw_input_error(cfg.rangecal_json, 0, "world_frame",
                      "its site origin (" + format_number("%.9f", o.lat_deg) + ", " +
                          format_number("%.9f", o.lon_deg) + ", " + format_number("%.3f", o.h_m) +
                          ") is not this mission's (" + format_number("%.9f", site.lat_deg) + ", " +
                          format_number("%.9f", site.lon_deg) + ", " + format_number("%.3f", site.h_m) +
                          "): its camera's pose is in another ENU frame");
  if (r.camera.intr.width_px != cfg.sensor.width_px || r.camera.intr.height_px != cfg.sensor.height_px)
    throw_input_error(cfg.rangecal_json, 0, "image_size_px",
                      "the file's image is " + std::to_string(r.camera.intr.width_px) + " × " +
                          std::to_string(r.camera.intr.height_px) + " px and camera " + cfg.id +
                          "'s sensor " + std::to_string(cfg.sensor.width_px) + " × " +
                          std::to_string(cfg.sensor.height_px));
  bool usable = false;
  out.covariance = camera_covariance(r, &usable);
  if (!usable)
    throw_input_error(cfg.rangecal_json, 0, "covariance",
                      "has no usable covariance: an imported calibration must bring its uncertainty");
  require_whole_covariance(out.covariance, cfg.rangecal_json);
  out.camera = r.camera;
  out.camera.id = cfg.id;
  return out;
}

}  // namespace

ImportedCalibration read_imported_calibration(const ImportedCameraConfig& cfg, const GeodeticOrigin& site) {
  const double dx = cfg.sensor.pixel_size_um[0] * 1e-3, dy = cfg.sensor.pixel_size_um[1] * 1e-3;
  ImportedCalibration out;
  if (!cfg.rangecal_json.empty()) return from_calibration_json(cfg, site);
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
