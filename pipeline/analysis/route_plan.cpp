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
    obs.push_back(mission_observations(m, c, o, &n_lamp));
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
