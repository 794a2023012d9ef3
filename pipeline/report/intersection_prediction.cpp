#include "pipeline/report/intersection_prediction.hpp"

#include <limits>

#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

PredictedIntersection predict_intersection(const std::vector<const CalibrationResult*>& cams,
                                           const Eigen::Vector3d& X_enu_m, double pick_sigma_px,
                                           const CrossCovariances* cross, bool weigh_calibration) {
  PredictedIntersection p;
  std::vector<TriangulationView> views;
  std::vector<std::size_t> seen;  // index into cams of each view
  for (std::size_t i = 0; i < cams.size(); ++i) {
    const CalibrationResult* c = cams[i];
    TriangulationView v;
    if (!(world_to_camera(c->camera.pose, X_enu_m).z() > 0) || !project(c->camera, X_enu_m, &v.uv_px) ||
        !inside_image(c->camera.intr, v.uv_px))
      continue;
    v.camera = c->camera;
    const auto n = static_cast<Eigen::Index>(c->parameters.size());
    if (n > 0 && c->covariance.rows() == n && c->covariance.cols() == n)
      v.calibration = {c->parameters, c->covariance};
    v.pick_sigma_px = pick_sigma_px;
    views.push_back(v);
    seen.push_back(i);
  }
  p.n_cameras = static_cast<int>(views.size());
  if (p.n_cameras < 2) return p;
  // The cross blocks of the cameras that see X, where they match their calibrations' parameters.
  CrossCovariances sub;
  if (cross) {
    sub.assign(views.size(), std::vector<Eigen::MatrixXd>(views.size()));
    for (std::size_t a = 0; a < views.size(); ++a)
      for (std::size_t b = 0; b < views.size(); ++b) {
        if (a == b || seen[a] >= cross->size() || seen[b] >= (*cross)[seen[a]].size()) continue;
        const Eigen::MatrixXd& S = (*cross)[seen[a]][seen[b]];
        if (S.rows() == static_cast<Eigen::Index>(views[a].calibration.parameters.size()) &&
            S.cols() == static_cast<Eigen::Index>(views[b].calibration.parameters.size()))
          sub[a][b] = S;
      }
  }
  const TriangulationResult t =
      triangulation_covariance_at(views, X_enu_m, cross ? &sub : nullptr, weigh_calibration);
  p.cov_calibration_m2 = t.cov_calibration_m2;
  p.cov_pick_m2 = t.cov_pick_m2;
  return p;
}

IntersectionSigmaSlice intersection_sigma_slice(const std::vector<const CalibrationResult*>& cams,
                                                const Eigen::Vector2d& e_range_m,
                                                const Eigen::Vector2d& n_range_m, double up_m, int nx, int ny,
                                                double pick_sigma_px, const CrossCovariances* cross) {
  IntersectionSigmaSlice s;
  s.up_m = up_m;
  for (int i = 0; i < nx; ++i) s.e_m.push_back(e_range_m[0] + (i + 0.5) * (e_range_m[1] - e_range_m[0]) / nx);
  for (int j = 0; j < ny; ++j) s.n_m.push_back(n_range_m[0] + (j + 0.5) * (n_range_m[1] - n_range_m[0]) / ny);
  s.sigma_m.resize(ny, nx);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const PredictedIntersection p =
          predict_intersection(cams, Eigen::Vector3d(s.e_m[i], s.n_m[j], up_m), pick_sigma_px, cross, false);
      s.sigma_m(j, i) = p.n_cameras >= 2 ? std::sqrt(p.cov_calibration_m2.trace())
                                         : std::numeric_limits<double>::quiet_NaN();
    }
  return s;
}

}  // namespace rangecal
