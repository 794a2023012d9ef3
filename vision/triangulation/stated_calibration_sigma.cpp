#include "vision/triangulation/stated_calibration_sigma.hpp"

#include <cmath>
#include <utility>
#include <vector>

#include "config/error.hpp"

namespace rangecal {

CameraCovariance stated_camera_covariance(const Camera& camera, const StatedCalibrationSigma& sigma) {
  for (const auto& [name, value] : {std::pair<const char*, double>{"focal_px", sigma.focal_px},
                                    {"principal_point_px", sigma.principal_point_px},
                                    {"position_m", sigma.position_m},
                                    {"rotation_mrad", sigma.rotation_mrad},
                                    {"image_px", sigma.image_px}})
    if (!(std::isfinite(value) && value >= 0))
      throw_input_error("", 0, name, "camera " + camera.id + ": a stated σ must be a finite number ≥ 0");
  using P = CameraParameter;
  const double rad = 1e-3 * sigma.rotation_mrad;
  const std::vector<std::pair<P, double>> sd = {{P::f, sigma.focal_px * camera.intr.dy_mm},
                                                {P::u0, sigma.principal_point_px},
                                                {P::v0, sigma.principal_point_px},
                                                {P::wx, rad},
                                                {P::wy, rad},
                                                {P::wz, rad},
                                                {P::CE, sigma.position_m},
                                                {P::CN, sigma.position_m},
                                                {P::CU, sigma.position_m}};
  CameraCovariance out;
  std::vector<double> var;
  for (const auto& [p, s] : sd)
    if (s > 0) {
      out.parameters.push_back(p);
      var.push_back(s * s);
    }
  out.covariance =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(var.size()), static_cast<Eigen::Index>(var.size()));
  for (std::size_t i = 0; i < var.size(); ++i)
    out.covariance(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) = var[i];
  return out;
}

}  // namespace rangecal
