#include "pipeline/analysis/network_plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>

#include "optim/network/network_covariance.hpp"
#include "optim/network/network_parameters.hpp"
#include "pipeline/simulate/ppk_error.hpp"

namespace rangecal {

namespace {

/// The pole top as a control point of `n` under the survey σ, seen by every camera whose image holds
/// it (with the pick σ); nothing when none does.
void add_control_pole(const Scenario& s, const ScenarioPole& pole, PlannedNetwork* n) {
  const std::size_t k = n->points.size();
  for (std::size_t c = 0; c < n->truth.size(); ++c) {
    Eigen::Vector2d uv;
    if (!project(n->truth[c], pole.enu_m, &uv) || !inside_image(n->truth[c].intr, uv)) continue;
    if (k == n->points.size()) {
      NetworkPoint p;
      p.prior_enu = pole.enu_m;
      p.prior_cov = Eigen::Matrix3d::Identity() * s.survey_noise_m * s.survey_noise_m;
      p.control_pole = true;
      p.quality = 0;
      p.source = "pole '" + pole.id + "'";
      n->points.push_back(p);
    }
    NetworkObservation ob;
    ob.camera = c, ob.point = k, ob.pixel = uv, ob.pixel_sigma_px = s.pick_noise_px;
    n->observations.push_back(ob);
  }
}

}  // namespace

PlannedNetwork planned_network(const Scenario& s, const PlanOptions& o) {
  return planned_network(simulate_mission(s), o);
}

PlannedNetwork planned_network(const SimMission& m, const PlanOptions& o) {
  const Scenario& s = m.scenario;
  PlannedNetwork n;
  n.ppk = stated_error_model(s.gnss.noise_sd_m, s.gnss.correlated_error);
  const std::int64_t max_ns = static_cast<std::int64_t>(std::llround(o.max_frame_offset_s * 1e9));
  std::map<std::size_t, std::size_t> point_of_epoch;
  for (std::size_t c = 0; c < m.cameras.size(); ++c) {
    const SimCamera& cam = m.cameras[c];
    n.truth.push_back(cam.spec.camera);
    std::vector<char> taken(cam.frames.size(), 0);
    for (std::size_t e = 0; e < m.epochs.size(); ++e) {
      const SimEpoch& ep = m.epochs[e];
      if (ep.quality != 1) continue;  // the simulated mission config accepts fix epochs only
      const std::size_t best =
          nearest_in_time(cam.frames, ep.utc, [](const SimFrame& f) { return f.stamp_utc; });
      if (best == cam.frames.size() || std::llabs(cam.frames[best].stamp_utc.ns - ep.utc.ns) > max_ns ||
          !cam.frames[best].in_view || taken[best])
        continue;
      taken[best] = 1;
      auto it = point_of_epoch.find(e);
      if (it == point_of_epoch.end()) {
        NetworkPoint p;
        p.prior_enu = ep.lamp_true;
        p.prior_cov = ep.sd_enu.cwiseProduct(ep.sd_enu).asDiagonal();
        p.quality = ep.quality;
        p.time_s = 1e-9 * static_cast<double>(ep.utc.ns - m.epochs.front().utc.ns);
        it = point_of_epoch.emplace(e, n.points.size()).first;
        n.points.push_back(p);
      }
      NetworkObservation ob;
      ob.camera = c;
      ob.point = it->second;
      ob.pixel = cam.frames[best].lamp_px;
      ob.pixel_sigma_px = o.pixel_sigma_px;
      ob.offset_m = cam.frames[best].lamp_enu - ep.lamp_true;
      ob.velocity = cam.frames[best].lamp_velocity_enu;
      n.observations.push_back(ob);
    }
  }
  const auto use = s.mission_calibrate.find("use_control_poles");
  if (use != s.mission_calibrate.end() && use->is_boolean() && use->get<bool>())
    for (const ScenarioPole& pole : s.poles)
      if (pole.role == "control") add_control_pole(s, pole, &n);
  return n;
}

PlannedNetwork with_survey(const PlannedNetwork& n, const Scenario& s, std::size_t control_poles,
                           double station_sigma_m) {
  PlannedNetwork out = n;
  // The control poles follow the lamp points (planned_network): cut them and their observations.
  std::size_t lamp = 0;
  while (lamp < out.points.size() && !out.points[lamp].control_pole) ++lamp;
  out.points.resize(lamp);
  out.observations.erase(std::remove_if(out.observations.begin(), out.observations.end(),
                                        [&](const NetworkObservation& ob) { return ob.point >= lamp; }),
                         out.observations.end());
  std::vector<const ScenarioPole*> order;
  for (const bool control : {true, false})
    for (const ScenarioPole& pole : s.poles)
      if ((pole.role == "control") == control) order.push_back(&pole);
  for (std::size_t k = 0; k < control_poles && k < order.size(); ++k) add_control_pole(s, *order[k], &out);
  out.priors.assign(out.truth.size(), BundlePriors{});
  if (station_sigma_m > 0)
    for (std::size_t c = 0; c < out.truth.size(); ++c) {
      out.priors[c].use_center = true;
      out.priors[c].center_enu_m = out.truth[c].pose.center();
      out.priors[c].center_sigma_m = Eigen::Vector3d::Constant(station_sigma_m);
    }
  return out;
}

Eigen::MatrixXd network_cramer_rao_bound(const PlannedNetwork& n, const std::vector<std::string>& free,
                                         double pixel_sigma_px, double image_factor) {
  std::vector<NetworkCamera> cams;
  for (const Camera& t : n.truth) {
    NetworkCamera c;
    c.initial = t;
    c.options.free = free;
    c.options.pixel_sigma_px = pixel_sigma_px;
    if (cams.size() < n.priors.size()) c.options.priors = n.priors[cams.size()];
    cams.push_back(c);
  }
  NetworkLayout l = make_network_layout(cams, n.points, n.observations, n.ppk);
  l.pixel_sigma_scale = 1 / image_factor;  // as the run's datum floor (network_adjustment.cpp)
  NetworkParameterBlocks b;
  for (const Camera& t : n.truth) b.cameras.push_back(BundleParameterBlocks::from_camera(t));
  for (const NetworkPoint& p : n.points)
    b.points.push_back({p.prior_enu.x(), p.prior_enu.y(), p.prior_enu.z()});
  b.gm.assign(l.gm_chain.size(), {0.0, 0.0, 0.0});
  const NetworkSelection sel{
      std::vector<char>(n.observations.size(), 1), std::vector<char>(n.points.size(), 1), {}, {}};
  return network_covariance(l, b, sel, 64, 10, 1e-14).joint;
}

}  // namespace rangecal
