#include "pipeline/report/intersection_prediction.hpp"

#include <Eigen/Cholesky>
#include <limits>

#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

PredictedIntersection predict_intersection(const std::vector<const CalibrationResult*>& cams,
                                           const Eigen::Vector3d& X_enu_m, double pick_sigma_px,
                                           const CrossCovariances* cross) {
  PredictedIntersection p;
  struct View {
    std::size_t camera = 0;  // index into cams
    Eigen::Matrix<double, 2, 3> Jx;
    Eigen::MatrixXd K;  // ∂pixel/∂θ (2 × parameters; empty without a covariance)
  };
  std::vector<View> views;
  Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < cams.size(); ++i) {
    const CalibrationResult* c = cams[i];
    Eigen::Vector2d uv;
    if (!(world_to_camera(c->camera.pose, X_enu_m).z() > 0) || !project(c->camera, X_enu_m, &uv) ||
        !inside_image(c->camera.intr, uv))
      continue;
    View v;
    v.camera = i;
    const auto n = static_cast<Eigen::Index>(c->parameters.size());
    const bool has_cov = n > 0 && c->covariance.rows() == n && c->covariance.cols() == n;
    const Eigen::MatrixXd K = pixel_jacobian_wrt_parameters(
        c->camera, has_cov ? c->parameters : std::vector<CameraParameter>{}, X_enu_m, &v.Jx);
    if (has_cov) v.K = K;
    N += v.Jx.transpose() * v.Jx;
    views.push_back(v);
  }
  p.n_cameras = static_cast<int>(views.size());
  if (p.n_cameras < 2) return p;
  const Eigen::Matrix3d Ninv = N.ldlt().solve(Eigen::Matrix3d::Identity());
  // Σ_cal = Σ_i Σ_j A_i K_i Σ_ij K_jᵀ A_jᵀ, A_i = N⁻¹J_iᵀ: the diagonal blocks are each camera's
  // covariance, the others the joint (network) covariance's cross blocks when given.
  for (const View& a : views) {
    if (a.K.size() == 0) continue;
    const Eigen::Matrix<double, 3, 2> Aa = Ninv * a.Jx.transpose();
    for (const View& b : views) {
      if (b.K.size() == 0) continue;
      const Eigen::Matrix<double, 3, 2> Ab = Ninv * b.Jx.transpose();
      Eigen::MatrixXd S;
      if (a.camera == b.camera) {
        S = cams[a.camera]->covariance;
      } else if (cross && a.camera < cross->size() && b.camera < (*cross)[a.camera].size() &&
                 (*cross)[a.camera][b.camera].rows() == a.K.cols() &&
                 (*cross)[a.camera][b.camera].cols() == b.K.cols()) {
        S = (*cross)[a.camera][b.camera];
      } else {
        continue;
      }
      p.cov_calibration_m2 += Aa * (a.K * S * b.K.transpose()) * Ab.transpose();
    }
  }
  p.cov_pick_m2 = pick_sigma_px * pick_sigma_px * Ninv;
  return p;
}

IntersectionSigmaSlice intersection_sigma_slice(const std::vector<const CalibrationResult*>& cams,
                                                const Eigen::Vector2d& e_range_m,
                                                const Eigen::Vector2d& n_range_m, double up_m, int nx, int ny,
                                                const CrossCovariances* cross) {
  IntersectionSigmaSlice s;
  s.up_m = up_m;
  for (int i = 0; i < nx; ++i) s.e_m.push_back(e_range_m[0] + (i + 0.5) * (e_range_m[1] - e_range_m[0]) / nx);
  for (int j = 0; j < ny; ++j) s.n_m.push_back(n_range_m[0] + (j + 0.5) * (n_range_m[1] - n_range_m[0]) / ny);
  s.sigma_m.resize(ny, nx);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const PredictedIntersection p =
          predict_intersection(cams, Eigen::Vector3d(s.e_m[i], s.n_m[j], up_m), 0, cross);
      s.sigma_m(j, i) = p.n_cameras >= 2 ? std::sqrt(p.cov_calibration_m2.trace())
                                         : std::numeric_limits<double>::quiet_NaN();
    }
  return s;
}

}  // namespace rangecal
