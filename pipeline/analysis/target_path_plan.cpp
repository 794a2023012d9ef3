#include "pipeline/analysis/target_path_plan.hpp"

#include <cmath>

#include "config/error.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {
namespace {

// The path at t (s): linear between the waypoints around it; the velocity that segment's.
void target_path_at(const std::vector<TargetPathPoint>& path, double t, Eigen::Vector3d* x,
                    Eigen::Vector3d* v) {
  std::size_t k = 1;
  while (k + 1 < path.size() && path[k].t_s < t) ++k;
  const TargetPathPoint& a = path[k - 1];
  const TargetPathPoint& b = path[k];
  const double w = (t - a.t_s) / (b.t_s - a.t_s);
  *x = (1 - w) * a.enu_m + w * b.enu_m;
  *v = (b.enu_m - a.enu_m) / (b.t_s - a.t_s);
}

}  // namespace

void check_target_path_options(const TargetPathOptions& options, const std::vector<TargetPathPoint>& path) {
  if (!(options.label_sigma_px > 0 && std::isfinite(options.label_sigma_px)))
    throw_config_error("", "--target-label-sigma", "must be a positive number of pixels");
  if (!(options.timing_sigma_s >= 0 && std::isfinite(options.timing_sigma_s)))
    throw_config_error("", "--target-timing-sigma", "must be a number of seconds ≥ 0");
  if (!(options.rate_hz > 0 && std::isfinite(options.rate_hz)))
    throw_config_error("", "--target-rate", "must be a positive number of instants per second");
  // Bounded work (docs/reliability.md): a million instants is hours of a fast target at 100 Hz.
  if (path.size() >= 2) {
    const double span = path.back().t_s - path.front().t_s;
    if (span * options.rate_hz > 1e6)
      throw_config_error(
          "", "--target-rate",
          "the path's " + std::to_string(span) + " s at this rate would be more than 1,000,000 instants");
  }
}

PlannedTargetPath plan_target_path(const std::vector<Camera>& truth,
                                   const std::vector<CameraParameter>& parameters,
                                   const Eigen::MatrixXd& joint, const std::vector<TargetPathPoint>& path,
                                   const TargetPathOptions& options) {
  check_target_path_options(options, path);
  const Eigen::Index p = static_cast<Eigen::Index>(parameters.size());
  const bool with_calibration =
      joint.rows() == p * static_cast<Eigen::Index>(truth.size()) && joint.size() > 0;
  PlannedTargetPath out;
  if (path.size() < 2) return out;
  const double span = path.back().t_s - path.front().t_s;
  const auto steps = static_cast<long>(std::floor(span * options.rate_hz + 1e-9));
  for (long k = 0; k <= steps; ++k) {
    PlannedTargetInstant at;
    at.t_s = path.front().t_s + static_cast<double>(k) / options.rate_hz;
    target_path_at(path, at.t_s, &at.enu_m, &at.velocity_mps);
    ++out.tried;
    std::vector<TriangulationView> views;
    std::vector<Eigen::Index> block;  // each view's camera's block of `joint`
    for (std::size_t c = 0; c < truth.size(); ++c) {
      TriangulationView v;
      if (!project(truth[c], at.enu_m, &v.uv_px) || !inside_image(truth[c].intr, v.uv_px)) continue;
      // The image velocity by a central difference over ±1 ms of the path's straight segment.
      Eigen::Vector2d ahead, behind;
      const double h = 1e-3;
      if (!project(truth[c], at.enu_m + h * at.velocity_mps, &ahead) ||
          !project(truth[c], at.enu_m - h * at.velocity_mps, &behind))
        continue;
      v.camera = truth[c];
      v.pick_sigma_px = options.label_sigma_px;
      v.timing_sigma_s = options.timing_sigma_s;
      v.image_velocity_px_s = (ahead - behind) / (2 * h);
      const Eigen::Index b = static_cast<Eigen::Index>(c) * p;
      if (with_calibration) v.calibration = {parameters, joint.block(b, b, p, p)};
      views.push_back(v);
      block.push_back(b);
      at.cameras.push_back(c);
    }
    if (views.size() < 2) {
      ++out.unseen;
      continue;
    }
    CrossCovariances cross;
    if (with_calibration) {
      cross.assign(views.size(), std::vector<Eigen::MatrixXd>(views.size()));
      for (std::size_t i = 0; i < views.size(); ++i)
        for (std::size_t j = 0; j < views.size(); ++j)
          if (i != j) cross[i][j] = joint.block(block[i], block[j], p, p);
    }
    try {
      const TriangulationResult r =
          triangulate_point(views, "the target's path", with_calibration ? &cross : nullptr);
      at.cov_m2 = r.cov_m2;
      at.sigma_m = r.sigma_m;
      at.labels_m = std::sqrt(std::max(0.0, r.cov_pick_m2.trace()));
      at.timing_m = std::sqrt(std::max(0.0, r.cov_timing_m2.trace()));
      at.calibration_m = std::sqrt(std::max(0.0, r.cov_calibration_m2.trace()));
    } catch (const Error& e) {
      if (e.kind() == ErrorKind::input) throw;
      ++out.unseen;  // rays nearly parallel: no point there
      continue;
    }
    out.instants.push_back(std::move(at));
  }
  return out;
}

}  // namespace rangecal
