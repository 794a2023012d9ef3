#include "pipeline/report/intersection_prediction.hpp"

#include <Eigen/Cholesky>
#include <limits>

#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

PredictedIntersection predict_intersection(const std::vector<const CalibrationResult*>& cams,
                                           const Eigen::Vector3d& X_enu_m, double pick_sigma_px) {
  PredictedIntersection p;
  struct View {
    Eigen::Matrix<double, 2, 3> Jx;
    Eigen::Matrix2d S;  // K Σθ Kᵀ (px²)
  };
  std::vector<View> views;
  Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
  for (const CalibrationResult* c : cams) {
    Eigen::Vector2d uv;
    if (!(world_to_camera(c->camera.pose, X_enu_m).z() > 0) || !project(c->camera, X_enu_m, &uv) ||
        !inside_image(c->camera.intr, uv))
      continue;
    View v;
    const auto n = static_cast<Eigen::Index>(c->parameters.size());
    const bool has_cov = n > 0 && c->covariance.rows() == n && c->covariance.cols() == n;
    const Eigen::MatrixXd K = pixel_jacobian_wrt_parameters(
        c->camera, has_cov ? c->parameters : std::vector<CameraParameter>{}, X_enu_m, &v.Jx);
    v.S = has_cov ? Eigen::Matrix2d(K * c->covariance * K.transpose()) : Eigen::Matrix2d::Zero();
    N += v.Jx.transpose() * v.Jx;
    views.push_back(v);
  }
  p.n_cameras = static_cast<int>(views.size());
  if (p.n_cameras < 2) return p;
  const Eigen::Matrix3d Ninv = N.ldlt().solve(Eigen::Matrix3d::Identity());
  for (const View& v : views) {
    const Eigen::Matrix<double, 3, 2> A = Ninv * v.Jx.transpose();
    p.cov_calibration_m2 += A * v.S * A.transpose();
  }
  p.cov_pick_m2 = pick_sigma_px * pick_sigma_px * Ninv;
  return p;
}

IntersectionSigmaSlice intersection_sigma_slice(const std::vector<const CalibrationResult*>& cams,
                                                const Eigen::Vector2d& e_range_m,
                                                const Eigen::Vector2d& n_range_m, double up_m, int nx,
                                                int ny) {
  IntersectionSigmaSlice s;
  s.up_m = up_m;
  for (int i = 0; i < nx; ++i) s.e_m.push_back(e_range_m[0] + (i + 0.5) * (e_range_m[1] - e_range_m[0]) / nx);
  for (int j = 0; j < ny; ++j) s.n_m.push_back(n_range_m[0] + (j + 0.5) * (n_range_m[1] - n_range_m[0]) / ny);
  s.sigma_m.resize(ny, nx);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const PredictedIntersection p =
          predict_intersection(cams, Eigen::Vector3d(s.e_m[i], s.n_m[j], up_m), 0);
      s.sigma_m(j, i) = p.n_cameras >= 2 ? std::sqrt(p.cov_calibration_m2.trace())
                                         : std::numeric_limits<double>::quiet_NaN();
    }
  return s;
}

}  // namespace rangecal
