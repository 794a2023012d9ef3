#include "pipeline/steps/calibration_problem.hpp"

#include <map>

#include "config/error.hpp"
#include "pipeline/mission/stage_options.hpp"

namespace rangecal {

ControlPoleViews read_control_pole_views(const MissionConfig& cfg, const CameraConfig& camera) {
  ControlPoleViews v;
  if (!cfg.calibrate.use_control_poles || cfg.poles_file.empty() || camera.pole_observations.empty())
    return v;
  v.survey = read_pole_survey(cfg.poles_file, cfg.origin);
  v.picks = read_pole_picks(camera.pole_observations, {camera.sensor.width_px, camera.sensor.height_px});
  v.survey_file = cfg.poles_file;
  v.picks_file = camera.pole_observations;
  return v;
}

CalibrationProblem make_calibration_problem(const CameraConfig& cam, const CalibrateConfig& calibrate,
                                            const std::vector<Correspondence>& pairs,
                                            const ControlPoleViews& poles) {
  CalibrationProblem p;
  p.camera_id = cam.id;
  p.sensor = sensor_geometry(cam.sensor);
  p.nominal_focal_mm = cam.nominal_focal_mm;
  p.priors = cam.priors;
  p.free = cam.free.empty() ? calibrate.free : cam.free;
  // A free principal point is held by its prior; without one given, the prior is the image centre
  // under principal_point_sigma_px (docs/config.md "The principal point").
  const std::vector<CameraParameter> free = expand_free_parameters(p.free);
  if (!p.priors.principal_point_px &&
      (contains(free, CameraParameter::u0) || contains(free, CameraParameter::v0)))
    p.priors.principal_point_px = Eigen::Vector2d(p.sensor.center_u_px(), p.sensor.center_v_px());
  // An imported track's labels stand where the centroids do: the camera's default σ, scaled by its
  // image variance component (docs/optimisation.md "Image variance components").
  p.pixel_sigma_px = cam.track ? cam.pixel_sigma.track_px : cam.pixel_sigma.centroid_px;
  p.seed = calibrate.seed;
  for (const Correspondence& c : pairs) {
    BundleObservation o;
    o.world = c.enu;
    o.pixel = c.uv;
    const Eigen::Vector3d sd = c.sd_enu ? *c.sd_enu : Eigen::Vector3d::Constant(kDefaultWorldSigmaM);
    o.world_cov = sd.cwiseProduct(sd).asDiagonal();
    if (c.vel_enu) o.velocity = *c.vel_enu;
    if (c.pixel_sigma_px) o.pixel_sigma_px = *c.pixel_sigma_px;  // stated: not the camera's, not scaled
    // The fix's place in a correlated PPK error model's Gauss–Markov process (BundleObservation::time_s).
    o.time_s = 1e-9 * static_cast<double>(c.utc.ns - pairs.front().utc.ns);
    if (c.line > 0) o.source = "correspondences line " + std::to_string(c.line);
    p.observations.push_back(o);
  }
  std::map<std::string, const SurveyedPole*> by_id;
  for (const auto& pole : poles.survey) by_id[pole.id] = &pole;
  for (const PolePick& pick : poles.picks) {
    const auto it = by_id.find(pick.id);
    if (it == by_id.end())
      throw_input_error(poles.picks_file, pick.line, "id",
                        "pole '" + pick.id + "' is not in the survey " + poles.survey_file);
    if (it->second->role != PoleRole::control) continue;  // check poles never calibrate
    BundleObservation o;
    o.world = it->second->enu;
    o.pixel = pick.uv;
    o.world_cov = Eigen::Matrix3d::Identity() * calibrate.control_sigma_m * calibrate.control_sigma_m;
    o.pixel_sigma_px = cam.pixel_sigma.pick_px;
    o.source = "control pole '" + pick.id + "' (" + poles.picks_file + ":" + std::to_string(pick.line) + ")";
    p.observations.push_back(o);
    p.control_pole_ids.push_back(pick.id);
  }
  return p;
}

BundleOptions bundle_options(const CalibrationProblem& p) {
  const std::vector<CameraParameter> free = expand_free_parameters(p.free);
  BundleOptions opt;
  opt.free = p.free;
  opt.pixel_sigma_px = p.pixel_sigma_px;
  opt.ppk_error = p.ppk_error;
  if (p.priors.principal_point_px &&
      (contains(free, CameraParameter::u0) || contains(free, CameraParameter::v0))) {
    opt.priors.use_principal_point = true;
    opt.priors.principal_point_px = *p.priors.principal_point_px;
    opt.priors.principal_point_sigma_px = p.priors.principal_point_sigma_px;
  }
  if (p.priors.center_enu_m && contains(free, CameraParameter::CE)) {
    opt.priors.use_center = true;
    opt.priors.center_enu_m = *p.priors.center_enu_m;
    opt.priors.center_sigma_m = Eigen::Vector3d::Constant(p.priors.center_sigma_m);
  }
  return opt;
}

}  // namespace rangecal
