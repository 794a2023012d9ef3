#include "pipeline/analysis/route_plan.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "config/error.hpp"
#include "pipeline/analysis/monte_carlo.hpp"
#include "pipeline/analysis/network_plan.hpp"
#include "pipeline/analysis/network_vs_per_camera.hpp"
#include "pipeline/simulate/mission_simulator.hpp"
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

/// Lamp points, then control poles when the mission uses them.
std::vector<BundleObservation> all_observations(const SimMission& m, const SimCamera& cam,
                                                const PlanOptions& o, std::size_t* n_lamp) {
  std::vector<BundleObservation> obs = observations_of(m, cam, o);
  *n_lamp = obs.size();
  for (const BundleObservation& p : control_pole_observations(m.scenario, cam.spec.camera)) obs.push_back(p);
  return obs;
}

}  // namespace

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
  return all_observations(m, m.cameras[camera_index], options, &n_lamp);
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

namespace {

/// Each parameter's σ, strongest correlation and flags from b->covariance (b->singular: all
/// undetermined); `F`, when given, the information the covariance inverts, for the σ inflation.
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

}  // namespace

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

namespace {

/// The network's bound split into cameras (NetworkBound); `per_camera` and `obs` give the points per
/// camera and the fastest lamp speed (the clock offset's rule) as for the per-camera bound.
NetworkBound network_bound(const PlannedNetwork& net, const std::vector<CameraBound>& per_camera,
                           const std::vector<std::vector<BundleObservation>>& obs,
                           const std::vector<std::string>& free, const PlanOptions& o) {
  NetworkBound nb;
  nb.shared_epochs = shared_epochs(net);
  nb.joint = network_cramer_rao_bound(net, free, o.pixel_sigma_px);
  nb.singular = nb.joint.size() == 0;
  const std::vector<CameraParameter> params = expand_free_parameters(free);
  const Eigen::Index p = static_cast<Eigen::Index>(params.size());
  for (std::size_t c = 0; c < per_camera.size(); ++c) {
    CameraBound b;
    b.camera_id = per_camera[c].camera_id;
    b.n_points = per_camera[c].n_points;
    b.free_parameters = params;
    b.singular = nb.singular;
    if (!b.singular)
      b.covariance = nb.joint.block(static_cast<Eigen::Index>(c) * p, static_cast<Eigen::Index>(c) * p, p, p);
    double max_speed = 0;
    for (const BundleObservation& ob : obs[c]) max_speed = std::max(max_speed, ob.velocity.norm());
    fill_parameter_bounds(net.truth[c], nullptr, max_speed, o, &b);
    nb.cameras.push_back(b);
  }
  return nb;
}

/// SurveyBenefit of `net` for free set `free` over the flight-volume points `volume`.
SurveyBenefit survey_benefit(const PlannedNetwork& net, const Scenario& s,
                             const std::vector<std::string>& free, const std::vector<Eigen::Vector3d>& volume,
                             const PlanOptions& o) {
  SurveyBenefit b;
  const std::vector<CameraParameter> params = expand_free_parameters(free);
  for (const std::size_t wanted : o.survey_control_poles) {
    const std::size_t k = std::min(wanted, s.poles.size());
    if (std::find(b.control_poles.begin(), b.control_poles.end(), k) != b.control_poles.end()) continue;
    b.control_poles.push_back(k);
    for (const bool surveyed : {false, true}) {
      const PlannedNetwork n = with_survey(net, s, k, surveyed ? kSurveyedStationSigmaM : 0);
      const double v = predicted_intersection_rms(
          n.truth, params, network_cramer_rao_bound(n, free, o.pixel_sigma_px), volume, true);
      (surveyed ? b.stations_surveyed_m : b.stations_free_m).push_back(v);
    }
  }
  return b;
}

}  // namespace

RoutePlanAnalysis analyse_route_plan(const Scenario& s, const std::string& name, const PlanOptions& o) {
  const SimMission m = simulate_mission(s);
  std::vector<std::vector<BundleObservation>> obs;
  for (const SimCamera& c : m.cameras) {
    std::size_t n_lamp = 0;
    obs.push_back(all_observations(m, c, o, &n_lamp));
    if (n_lamp < 6)
      throw_calibration_error(s.file + " camera " + c.spec.id,
                              "the routes give only " + std::to_string(n_lamp) +
                                  " lamp points in view; the camera cannot be calibrated from them");
  }
  // The same observations as the network sees them (one point per epoch, shared by the cameras
  // that see it), for the network's bound and the per-camera cross-covariances.
  const PlannedNetwork net = planned_network(m, o);
  const std::vector<Eigen::Vector3d> volume = flight_volume_points(net, o.volume_points, o.volume_seed);
  RoutePlanAnalysis a;
  a.name = name;
  for (const std::vector<std::string>& free : o.free_sets) {
    FreeSetPlan fp;
    fp.free = free;
    for (std::size_t c = 0; c < m.cameras.size(); ++c) {
      Camera truth = m.cameras[c].spec.camera;
      truth.id = m.cameras[c].spec.id;
      fp.cameras.push_back(cramer_rao_bound(truth, obs[c], free, o));
    }
    fp.network = network_bound(net, fp.cameras, obs, free, o);
    const std::vector<CameraParameter> params = expand_free_parameters(free);
    const Eigen::MatrixXd per_camera = per_camera_joint_covariance(net, free, o);
    VolumeIntersection& v = fp.volume;
    v.n_points = static_cast<int>(volume.size());
    v.per_camera_m = predicted_intersection_rms(net.truth, params, per_camera, volume, true);
    v.per_camera_independent_m = predicted_intersection_rms(net.truth, params, per_camera, volume, false);
    v.network_m = predicted_intersection_rms(net.truth, params, fp.network.joint, volume, true);
    v.network_independent_m = predicted_intersection_rms(net.truth, params, fp.network.joint, volume, false);
    if (&free == &o.free_sets.front()) fp.survey = survey_benefit(net, s, free, volume, o);
    if (fp.network.applies())
      v.network_datum_floor_m = predicted_intersection_rms(
          net.truth, params, network_cramer_rao_bound(net, free, o.pixel_sigma_px, kDatumFloorImageFactor),
          volume, true);
    // The poles' σ under the calibration the run would make: the network's joint covariance when
    // the cameras share epochs (the run's default), else the per-camera calibrations with the
    // cross-covariances their shared fixes give them — as the intersect stage states them.
    const bool network = fp.network.applies() && !fp.network.singular;
    const Eigen::MatrixXd& joint = network ? fp.network.joint : per_camera;
    const Eigen::Index np = static_cast<Eigen::Index>(params.size());
    for (const ScenarioPole& pole : s.poles) {
      PoleBound pb;
      pb.id = pole.id;
      pb.role = pole.role;
      std::vector<TriangulationView> views;
      std::vector<Eigen::Index> block;  // each view's camera's first row in `joint`
      bool all_bounded = true;
      for (std::size_t c = 0; c < m.cameras.size(); ++c) {
        TriangulationView v;
        v.camera = m.cameras[c].spec.camera;
        v.camera.id = m.cameras[c].spec.id;
        if (!project(v.camera, pole.enu_m, &v.uv_px) || !inside_image(v.camera.intr, v.uv_px)) continue;
        all_bounded = all_bounded && !fp.cameras[c].singular;
        block.push_back(static_cast<Eigen::Index>(c) * np);
        v.calibration.parameters = fp.cameras[c].free_parameters;
        v.calibration.covariance = fp.cameras[c].covariance;
        v.pick_sigma_px = s.pick_noise_px;
        views.push_back(v);
      }
      pb.n_cameras = static_cast<int>(views.size());
      if (views.size() < 2 || !all_bounded) {
        fp.poles.push_back(pb);
        continue;
      }
      // Parallel rays or a pole behind a camera: no prediction, shown as "-".
      try {
        pb.per_camera_independent_sigma_m = triangulate_point(views, "pole " + pole.id).sigma_m;
      } catch (const Error&) {
      }
      if (joint.size() > 0) {
        CrossCovariances cross(views.size(), std::vector<Eigen::MatrixXd>(views.size()));
        for (std::size_t i = 0; i < views.size(); ++i) {
          views[i].calibration.covariance = joint.block(block[i], block[i], np, np);
          for (std::size_t j = 0; j < views.size(); ++j)
            if (i != j) cross[i][j] = joint.block(block[i], block[j], np, np);
        }
        try {
          pb.sigma_m = triangulate_point(views, "pole " + pole.id, &cross).sigma_m;
        } catch (const Error&) {
        }
      }
      fp.poles.push_back(pb);
    }
    a.free_sets.push_back(fp);
  }
  return a;
}

}  // namespace rangecal
