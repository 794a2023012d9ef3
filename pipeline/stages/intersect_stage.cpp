#include "pipeline/stages/intersect_stage.hpp"

#include <cmath>
#include <filesystem>
#include <limits>
#include <set>

#include "config/error.hpp"
#include "gnss/formats/pole_survey_csv.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/intersect_record.hpp"
#include "pipeline/io/intersection_csv.hpp"
#include "pipeline/io/network_json.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/stages/stage_inputs.hpp"
#include "pipeline/steps/intersection.hpp"

namespace rangecal {

namespace {

bool any_camera_has_picks(const MissionConfig& cfg) {
  for (const CameraConfig& cam : cfg.cameras)
    if (!cam.pole_observations.empty()) return true;
  return false;
}

/// Metres rounded to 1 µm for run.json (readable); a figure that was not computed (no pole to
/// average) is NaN, which run.json holds as null, so that nothing downstream prints "nan".
double um(double v) {
  return std::isfinite(v) ? std::round(v * 1e6) / 1e6 : std::numeric_limits<double>::quiet_NaN();
}

int cameras_with_picks(const MissionConfig& cfg) {
  int n = 0;
  for (const CameraConfig& cam : cfg.cameras) n += cam.pole_observations.empty() ? 0 : 1;
  return n;
}

/// The intersection check's shortfall (docs/reliability.md "Run outcome"), "" when it had what it
/// needs. The check is configured when the mission has a survey and two or more cameras have pole
/// picks; it then needs a check pole triangulated (its ΔR is the headline), or, when the calibrated
/// cameras picked no check pole, at least one surveyed pole.
std::string intersection_shortfall(const MissionConfig& cfg, const std::vector<SurveyedPole>& survey,
                                   const std::set<std::string>& picked_ids,
                                   const std::vector<std::string>& used, const IntersectionResult& result) {
  if (cameras_with_picks(cfg) < 2) return "";
  bool check_picked = false;
  for (const SurveyedPole& p : survey)
    check_picked = check_picked || (p.role == PoleRole::check && picked_ids.count(p.id));
  if (check_picked ? result.check.n > 0 : result.check.n + result.control.n > 0) return "";
  std::string cams;
  for (const std::string& c : used) cams += (cams.empty() ? "" : ", ") + c;
  const std::string what = check_picked ? "no check pole" : "no surveyed pole";
  const std::string why =
      used.size() < 2 ? "only " + std::to_string(used.size()) + " calibrated camera has pole picks (" + cams +
                            "); a pole needs two"
                      : "none is picked in two calibrated cameras with a triangulation (see the warnings)";
  return what + " was triangulated, so the intersection check has no dR: " + why;
}

IntersectMeansRecord means_record(const IntersectionMeans& m) {
  IntersectMeansRecord r;
  r.n = m.n;
  r.mean_abs_dE_m = um(m.mean_abs_d.x());
  r.mean_abs_dN_m = um(m.mean_abs_d.y());
  r.mean_abs_dU_m = um(m.mean_abs_d.z());
  r.mean_dR_m = um(m.mean_dR);
  r.max_dR_m = um(m.max_dR);
  r.rms_dR_m = um(m.rms_dR);
  r.mean_sigma_m = um(m.mean_sigma_m);
  return r;
}

}  // namespace

void require_intersect_inputs(const MissionConfig& cfg) {
  if (cfg.poles_file.empty())
    throw_input_error(
        cfg.config_path, 0, "poles",
        "no pole survey in the config; the intersect stage needs \"poles\" (docs/formats.md) and "
        "cameras' \"pole_observations\"");
  if (!any_camera_has_picks(cfg))
    throw_input_error(cfg.config_path, 0, "cameras[].pole_observations",
                      "no camera has pole picks; the intersect stage needs \"pole_observations\" "
                      "(id,u,v) for at least two cameras");
}

StageLog run_intersect_stage(const MissionConfig& cfg) {
  StageLog log;
  log.stage = "intersect";
  if (cfg.poles_file.empty() || !any_camera_has_picks(cfg)) {
    // A mission without poles is a valid mission: the full run goes on (see the header).
    log.warnings.push_back("no poles: intersection skipped");
    IntersectRecord record;
    record.skipped =
        cfg.poles_file.empty() ? "no \"poles\" in the config" : "no camera has \"pole_observations\"";
    log.counts = intersect_record_json(record);
    return log;
  }

  const std::vector<SurveyedPole> survey = read_pole_survey(cfg.poles_file, cfg.origin);
  std::vector<IntersectCamera> cameras;
  std::vector<std::string> missing;
  IntersectRecord record;
  std::vector<std::string>& used = record.cameras_used;
  std::set<std::string> picked_ids;
  bool all_network = true;  // every used calibration comes from the one network of network.json
  std::vector<std::string> ids;
  std::vector<std::vector<CameraParameter>> parameters;
  for (const CameraConfig& cc : cfg.cameras) {
    if (cc.pole_observations.empty()) continue;
    const std::optional<CalibratedCamera> calibrated =
        read_calibrated_camera(cfg, cc.id, "sigma_m counts pick noise", &log.warnings);
    if (!calibrated) {
      missing.push_back(camera_output(cfg, cc.id, kCalibrationJson));
      continue;
    }
    const CalibrationResult& cal = calibrated->result;
    const bool usable = calibrated->usable;
    IntersectCamera ic;
    ic.id = cc.id;
    ic.camera = cal.camera;
    ic.calibration = calibrated->covariance;
    ic.picks = read_pole_picks(cc.pole_observations, {cal.camera.intr.width_px, cal.camera.intr.height_px});
    for (const PolePick& p : ic.picks) picked_ids.insert(p.id);
    all_network = all_network && cal.method == "network" && usable;
    ids.push_back(cc.id);
    parameters.push_back(ic.calibration.parameters);
    used.push_back(cc.id);
    cameras.push_back(std::move(ic));
  }
  if (cameras.empty()) {
    std::string list;
    for (const auto& m : missing) list += (list.empty() ? "" : ", ") + m;
    throw_input_error(missing.front(), 0, "",
                      "no camera with pole picks is calibrated (missing: " + list +
                          "); run rangecal calibrate CONFIG first");
  }

  // Cameras calibrated together are correlated through the shared lamp positions: the predicted σ
  // takes the cross blocks of the network's joint covariance (docs/intersection.md).
  CrossCovariances cross;
  if (all_network && cameras.size() >= 2) {
    cross = read_network_cross_covariances(mission_output(cfg, kNetworkJson), ids, &parameters);
    if (cross.empty())
      log.warnings.push_back(
          "the calibrations come from the network but " + mission_output(cfg, kNetworkJson) +
          " does not hold their joint covariance: sigma_m takes the cameras as independent");
  }
  record.joint_covariance = !cross.empty();
  const IntersectionResult result =
      intersect_poles(cameras, survey, cfg.intersect.pick_sigma_px, cross.empty() ? nullptr : &cross);
  for (const std::string& w : result.warnings) log.warnings.push_back(w);
  const std::vector<IntersectionRow> rows = intersection_rows(result);
  write_intersection_csv(mission_output(cfg, kIntersectionCsv), rows);

  int unsurveyed = 0;
  for (const PoleIntersection& p : result.poles) unsurveyed += p.surveyed ? 0 : 1;
  record.pick_sigma_px = cfg.intersect.pick_sigma_px;
  record.poles_picked = picked_ids.size();
  record.poles_triangulated = result.poles.size();
  record.unsurveyed_poles = unsurveyed;
  record.check = means_record(result.check);
  record.control = means_record(result.control);
  record.warnings = log.warnings.size();
  log.counts = intersect_record_json(record);
  if (const std::string s = intersection_shortfall(cfg, survey, picked_ids, used, result); !s.empty())
    log.shortfalls.push_back(s);
  return log;
}

}  // namespace rangecal
