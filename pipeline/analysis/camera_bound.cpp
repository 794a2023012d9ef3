#include "pipeline/analysis/camera_bound.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "config/error.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {
namespace {

constexpr double kUnbounded = std::numeric_limits<double>::infinity();
constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

/// Frames of one camera with their epochs: what the align stage keeps (docs/alignment.md: for every
/// lamp-track epoch the nearest frame, kept within max_frame_offset_s), lamp in view.
std::vector<BundleObservation> observations_of(const SimMission& m, const SimCamera& cam,
                                               const PlanOptions& o) {
  std::vector<BundleObservation> out;
  std::set<std::size_t> used;
  const auto& frames = cam.frames;
  const std::int64_t max_ns = static_cast<std::int64_t>(std::llround(o.max_frame_offset_s * 1e9));
  for (const SimEpoch& e : m.epochs) {
    if (e.quality != 1) continue;  // the simulated mission config accepts fix epochs only
    const std::size_t best = nearest_in_time(frames, e.utc, [](const SimFrame& f) { return f.stamp_utc; });
    if (best == frames.size() || std::llabs(frames[best].stamp_utc.ns - e.utc.ns) > max_ns ||
        !frames[best].in_view || used.count(best))
      continue;
    used.insert(best);
    BundleObservation ob;
    ob.world = frames[best].lamp_enu;
    ob.pixel = frames[best].lamp_px;
    ob.world_cov = e.sd_enu.cwiseProduct(e.sd_enu).asDiagonal();
    ob.pixel_sigma_px = o.pixel_sigma_px;
    ob.velocity = frames[best].lamp_velocity_enu;
    out.push_back(ob);
  }
  return out;
}

/// The control poles the mission would calibrate with (mission_calibrate.use_control_poles): each
/// pole top inside the image, surveyed with the scenario's survey σ and picked with its pick σ.
std::vector<BundleObservation> control_pole_observations(const Scenario& s, const Camera& cam) {
  std::vector<BundleObservation> out;
  const auto use = s.mission_calibrate.find("use_control_poles");
  if (use == s.mission_calibrate.end() || !use->is_boolean() || !use->get<bool>()) return out;
  for (const ScenarioPole& pole : s.poles) {
    if (pole.role != "control") continue;
    BundleObservation ob;
    if (!project(cam, pole.enu_m, &ob.pixel) || !inside_image(cam.intr, ob.pixel)) continue;
    ob.world = pole.enu_m;
    ob.world_cov = Eigen::Matrix3d::Identity() * s.survey_noise_m * s.survey_noise_m;
    ob.pixel_sigma_px = s.pick_noise_px;
    out.push_back(ob);
  }
  return out;
}

}  // namespace

std::vector<BundleObservation> mission_observations(const SimMission& m, const SimCamera& cam,
                                                    const PlanOptions& o, std::size_t* n_lamp) {
  std::vector<BundleObservation> obs = observations_of(m, cam, o);
  *n_lamp = obs.size();
  for (const BundleObservation& p : control_pole_observations(m.scenario, cam.spec.camera)) obs.push_back(p);
  return obs;
}

std::vector<std::vector<std::string>> default_plan_free_sets() {
  std::vector<std::string> with_pp = default_free_parameters();
  with_pp.push_back(parameter_name(CameraParameter::u0));
  with_pp.push_back(parameter_name(CameraParameter::v0));
  return {default_free_parameters(), with_pp};
}

std::vector<std::string> scenario_free_parameters(const Scenario& s) {
  const auto it =
      s.mission_calibrate.is_object() ? s.mission_calibrate.find("free") : s.mission_calibrate.end();
  if (!s.mission_calibrate.is_object() || it == s.mission_calibrate.end()) return default_free_parameters();
  std::vector<std::string> free;
  if (it->is_array())
    for (const nlohmann::json& x : *it)
      if (x.is_string()) free.push_back(x.get<std::string>());
  if (!it->is_array() || free.size() != it->size() || free.empty())
    throw_config_error(s.file, "mission_calibrate.free", "must be a non-empty list of parameter names");
  expand_free_parameters(free, s.file, "mission_calibrate.free");
  return free;
}

std::vector<BundleObservation> planned_observations(const Scenario& s, std::size_t camera_index,
                                                    const PlanOptions& options) {
  const SimMission m = simulate_mission(s);
  if (camera_index >= m.cameras.size())
    throw_config_error(s.file, "cameras", "no camera " + std::to_string(camera_index));
  std::size_t n_lamp = 0;
  return mission_observations(m, m.cameras[camera_index], options, &n_lamp);
}

ObservationTerms observation_terms(const Camera& truth, const std::vector<CameraParameter>& params,
                                   const BundleObservation& ob, double default_pixel_sigma_px) {
  ObservationTerms t;
  t.J = pixel_jacobian_wrt_parameters(truth, params, ob.world, &t.Jx);
  // The clock offset δ moves the seen point by −v·δ (optim/bundle/bundle_adjustment.hpp).
  for (std::size_t k = 0; k < params.size(); ++k)
    if (params[k] == CameraParameter::clock_offset)
      t.J.col(static_cast<Eigen::Index>(k)) = -t.Jx * ob.velocity;
  const double sp = ob.pixel_sigma_px > 0 ? ob.pixel_sigma_px : default_pixel_sigma_px;
  // Effective pixel covariance: centroid noise + PPK noise seen through the camera (as the bundle).
  t.C = sp * sp * Eigen::Matrix2d::Identity() + t.Jx * ob.world_cov * t.Jx.transpose();
  return t;
}

void fill_parameter_bounds(const Camera& truth, const Eigen::MatrixXd* F, double max_speed,
                           const PlanOptions& o, CameraBound* b) {
  const int n = static_cast<int>(b->free_parameters.size());
  b->parameters.clear();
  for (int i = 0; i < n; ++i) {
    ParameterBound p;
    p.parameter = b->free_parameters[i];
    p.value = parameter_value(truth, p.parameter, truth);
    if (b->singular) {
      p.sigma = kUnbounded;
      p.max_abs_correlation = kNoValue;
      p.poorly_determined = true;
    } else {
      const Eigen::MatrixXd& cov = b->covariance;
      p.sigma = std::sqrt(cov(i, i));
      for (int j = 0; j < n; ++j) {
        if (j == i) continue;
        const double r = std::abs(cov(i, j) / std::sqrt(cov(i, i) * cov(j, j)));
        if (r > p.max_abs_correlation)
          p.max_abs_correlation = r, p.correlated_with = parameter_name(b->free_parameters[j]);
      }
      p.sigma_inflation = F ? std::sqrt((*F)(i, i) * cov(i, i)) : kNoValue;
      const bool principal_point = p.parameter == CameraParameter::u0 || p.parameter == CameraParameter::v0;
      p.poorly_determined =
          p.max_abs_correlation > o.correlation_limit ||
          (principal_point && p.sigma > o.principal_point_limit_px) ||
          (p.parameter == CameraParameter::clock_offset && p.sigma * max_speed > o.clock_offset_limit_m);
    }
    b->parameters.push_back(p);
  }
}

CameraBound cramer_rao_bound(const Camera& truth, const std::vector<BundleObservation>& obs,
                             const std::vector<std::string>& free, const PlanOptions& o) {
  CameraBound b;
  b.camera_id = truth.id;
  b.n_points = static_cast<int>(obs.size());
  b.free_parameters = expand_free_parameters(free);
  const int n = static_cast<int>(b.free_parameters.size());
  Eigen::MatrixXd F = Eigen::MatrixXd::Zero(n, n);
  double max_speed = 0;  // m/s, for the clock offset's rule
  for (const BundleObservation& ob : obs) {
    max_speed = std::max(max_speed, ob.velocity.norm());
    const ObservationTerms t = observation_terms(truth, b.free_parameters, ob, o.pixel_sigma_px);
    F += t.J.transpose() * t.C.inverse() * t.J;
  }
  // Column scaling makes the rank test independent of the parameters' units.
  const Eigen::VectorXd d = F.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd Fs = d.asDiagonal() * F * d.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Fs);
  const Eigen::VectorXd ev = es.eigenvalues();
  b.singular = n == 0 || !(ev.minCoeff() > o.rank_tolerance * ev.maxCoeff());
  if (!b.singular) {
    const Eigen::MatrixXd Fs_inv =
        es.eigenvectors() * ev.cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
    b.covariance = d.asDiagonal() * Fs_inv * d.asDiagonal();
  }
  fill_parameter_bounds(truth, &F, max_speed, o, &b);
  return b;
}

}  // namespace rangecal
