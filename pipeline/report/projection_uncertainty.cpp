#include "pipeline/report/projection_uncertainty.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

Eigen::Vector3d point_on_pixel_ray(const Camera& cam, const Eigen::Vector2d& uv_px, double depth_m) {
  const Eigen::Vector3d ray = pixel_ray_world(cam, uv_px);
  // The ray's depth per metre along it is its component on the optical axis (R's third row).
  const double per_m = cam.pose.R.row(2).dot(ray);
  return cam.pose.center() + ray * (depth_m / per_m);
}

Eigen::Matrix2d projection_covariance_px2(const CalibrationResult& cal, const Eigen::Vector3d& X_enu_m) {
  const auto n = static_cast<Eigen::Index>(cal.parameters.size());
  if (n == 0 || cal.covariance.rows() != n || cal.covariance.cols() != n) return Eigen::Matrix2d::Zero();
  if (!(world_to_camera(cal.camera.pose, X_enu_m).z() > 0))
    return Eigen::Matrix2d::Constant(std::numeric_limits<double>::quiet_NaN());
  const Eigen::MatrixXd J = pixel_jacobian_wrt_parameters(cal.camera, cal.parameters, X_enu_m);
  return J * cal.covariance * J.transpose();
}

double projection_sigma_px(const CalibrationResult& cal, const Eigen::Vector2d& uv_px, double depth_m) {
  const Eigen::Matrix2d S = projection_covariance_px2(cal, point_on_pixel_ray(cal.camera, uv_px, depth_m));
  if (!S.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector2d ev =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(S, Eigen::EigenvaluesOnly).eigenvalues();
  return std::sqrt(std::max(0.0, ev.maxCoeff()));
}

ProjectionUncertaintyMap projection_uncertainty_map(const CalibrationResult& cal, double depth_m, int nx,
                                                    int ny) {
  ProjectionUncertaintyMap m;
  m.depth_m = depth_m;
  const double W = cal.camera.intr.width_px, H = cal.camera.intr.height_px;
  for (int i = 0; i < nx; ++i) m.u_px.push_back(-0.5 + (i + 0.5) * W / nx);
  for (int j = 0; j < ny; ++j) m.v_px.push_back(-0.5 + (j + 0.5) * H / ny);
  m.sigma_px.resize(ny, nx);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      m.sigma_px(j, i) = projection_sigma_px(cal, Eigen::Vector2d(m.u_px[i], m.v_px[j]), depth_m);
  return m;
}

double median_depth_m(const Camera& cam, const std::vector<Correspondence>& pairs) {
  std::vector<double> z;
  for (const Correspondence& p : pairs) {
    const double d = world_to_camera(cam.pose, p.enu).z();
    if (d > 0) z.push_back(d);
  }
  if (z.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::nth_element(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(z.size() / 2), z.end());
  return z[z.size() / 2];
}

}  // namespace rangecal
