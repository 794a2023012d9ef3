#include "pipeline/demo/demo.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/formats/pole_survey_csv.hpp"
#include "optim/bundle/whitening.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/lamp_track_adjusted_csv.hpp"
#include "pipeline/io/network_json.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/residuals_csv.hpp"
#include "pipeline/stages/mission_runner.hpp"
#include "pipeline/steps/calibration_problem.hpp"
#include "vision/triangulation/calibration_covariance.hpp"

namespace rangecal {
namespace {

// Expected RMS reprojection error of a perfect calibration: each used lamp point's world σ pushed
// through the true camera's Jacobian, plus the centroid σ on both axes. `used` follows `pairs`
// (residuals.csv's lamp rows; empty: all used).
double expected_rms_px(const Camera& truth, const std::vector<Correspondence>& pairs,
                       const std::vector<bool>& used, double centroid_sigma_px) {
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Correspondence& c = pairs[i];
    if (i < used.size() && !used[i]) continue;
    const Eigen::Vector3d sd = c.sd_enu ? *c.sd_enu : Eigen::Vector3d::Constant(kDefaultWorldSigmaM);
    if (!(world_to_camera(truth.pose, c.enu).z() > 0)) continue;
    const Eigen::Matrix<double, 2, 3> J = pixel_jacobian_wrt_world(truth, c.enu);
    const Eigen::Matrix2d cov = J * sd.cwiseAbs2().asDiagonal() * J.transpose();
    sum += cov.trace() + 2 * centroid_sigma_px * centroid_sigma_px;
    ++n;
  }
  return n > 0 ? std::sqrt(sum / n) : 0;
}

// The network's RMS reprojection error against its adjusted lamp positions over the lamp pairs it
// used: each pair at its frame time plus the correction (adjusted − fix) of its epoch, the nearest
// one in lamp_track_adjusted.csv, seen at the camera's clock offset as the network sees it
// (optim/network/network_observation.hpp). NaN without a pair to measure.
double network_rms_adjusted_px(const CalibrationResult& network, const std::vector<Correspondence>& pairs,
                               const std::vector<bool>& used,
                               const std::vector<LampTrackAdjustedRow>& adjusted) {
  double ss = 0;
  int n = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Correspondence& c = pairs[i];
    if ((i < used.size() && !used[i]) || adjusted.empty()) continue;
    const auto after = std::lower_bound(adjusted.begin(), adjusted.end(), c.utc,
                                        [](const LampTrackAdjustedRow& r, UtcTime t) { return r.utc < t; });
    auto nearest = after == adjusted.end() ? std::prev(after) : after;
    if (after != adjusted.begin() && after != adjusted.end() &&
        c.utc.ns - std::prev(after)->utc.ns < after->utc.ns - c.utc.ns)
      nearest = std::prev(after);
    const Eigen::Vector3d seen =
        c.enu + nearest->correction - c.vel_enu.value_or(Eigen::Vector3d::Zero()) * network.clock_offset_s;
    Eigen::Vector2d uv;
    if (!project(network.camera, seen, &uv)) continue;
    ss += (c.uv - uv).squaredNorm();
    ++n;
  }
  return n > 0 ? std::sqrt(ss / n) : std::nan("");
}

// The method calibration.json holds: the configured one, or the calibrate stage's default choice
// (docs/config.md "Default method"), as the first calibrated camera's file says.
std::string main_method(const MissionConfig& cfg) {
  if (!cfg.calibrate.method.empty()) return cfg.calibrate.method;
  for (const CameraConfig& cc : cfg.cameras) {
    const std::string path = camera_output(cfg, cc.id, kCalibrationJson);
    if (std::filesystem::exists(path)) return read_calibration_json(path).method;
  }
  return "bundle";
}

}  // namespace

DemoResults collect_demo_results(const SimMission& m, const MissionConfig& cfg) {
  DemoResults out;
  out.method = main_method(cfg);
  std::vector<std::string> methods{out.method};
  // The network keeps its per-camera start as calibration_bundle.json: shown beside it.
  if (out.method == "network") methods.push_back("bundle");
  for (const auto& c : cfg.calibrate.compare)
    if (std::find(methods.begin(), methods.end(), c) == methods.end()) methods.push_back(c);
  auto calibration_file = [&](const std::string& cam, const std::string& method) {
    return camera_output(
        cfg, cam, method == out.method ? std::string(kCalibrationJson) : compare_calibration_json(method));
  };

  for (const CameraConfig& cc : cfg.cameras) {
    DemoCamera d;
    d.id = cc.id;
    for (const SimCamera& sc : m.cameras)
      if (sc.spec.id == cc.id) d.truth = sc.spec.camera;
    for (const std::string& meth : methods) {
      const std::string path = calibration_file(cc.id, meth);
      if (std::filesystem::exists(path)) d.by_method[meth] = read_calibration_json(path);
    }
    const std::string corr = camera_output(cfg, cc.id, kCorrespondencesCsv);
    const std::string residuals = camera_output(cfg, cc.id, kResidualsCsv);
    std::vector<bool> used;
    if (std::filesystem::exists(residuals))
      for (const ResidualRow& r : read_residuals_csv(residuals))
        if (r.kind == ResidualRow::Kind::lamp) used.push_back(r.used);
    if (std::filesystem::exists(corr)) {
      const std::vector<Correspondence> pairs = read_correspondences_csv(corr);
      d.expected_rms_px = expected_rms_px(d.truth, pairs, used, 0.05);
      // residuals.csv is the main calibration's: the network's when it ran.
      const auto net = d.by_method.find("network");
      const std::string adjusted = mission_output(cfg, kLampTrackAdjustedCsv);
      if (out.method == "network" && net != d.by_method.end() && std::filesystem::exists(adjusted))
        d.network_rms_adjusted_px =
            network_rms_adjusted_px(net->second, pairs, used, read_lamp_track_adjusted_csv(adjusted));
    }
    out.cameras.push_back(std::move(d));
  }

  if (cfg.poles_file.empty()) return out;
  const std::vector<SurveyedPole> survey = read_pole_survey(cfg.poles_file, cfg.origin);
  for (const std::string& meth : methods) {
    std::vector<IntersectCamera> cams;
    for (std::size_t i = 0; i < cfg.cameras.size(); ++i) {
      const CameraConfig& cc = cfg.cameras[i];
      const auto it = out.cameras[i].by_method.find(meth);
      if (cc.pole_observations.empty() || it == out.cameras[i].by_method.end()) continue;
      IntersectCamera ic;
      ic.id = cc.id;
      ic.camera = it->second.camera;
      ic.calibration = camera_covariance(it->second);
      ic.picks = read_pole_picks(cc.pole_observations, {cc.sensor.width_px, cc.sensor.height_px});
      cams.push_back(std::move(ic));
    }
    if (cams.size() < 2) continue;
    // The network's cameras are correlated: its σ uses network.json's cross blocks, as the
    // intersect stage does.
    CrossCovariances cross;
    if (meth == "network") {
      std::vector<std::string> ids;
      std::vector<std::vector<CameraParameter>> parameters;
      for (const IntersectCamera& ic : cams)
        ids.push_back(ic.id), parameters.push_back(ic.calibration.parameters);
      cross = read_network_cross_covariances(mission_output(cfg, kNetworkJson), ids, &parameters);
    }
    DemoIntersection di;
    di.method = meth;
    di.result = intersect_poles(cams, survey, cfg.intersect.pick_sigma_px, cross.empty() ? nullptr : &cross);
    double sum = 0;
    for (const PoleIntersection& p : di.result.poles) {
      if (!p.surveyed || p.role != PoleRole::check) continue;
      for (const SimPole& sp : m.poles)
        if (sp.truth.id == p.id) {
          const double e = (p.enu - sp.truth.enu_m).norm();
          di.check_poles.push_back({p.id, p.enu - sp.truth.enu_m, p.cov_m2});
          sum += e;
          di.max_dR_truth_m = std::max(di.max_dR_truth_m, e);
          ++di.n_check;
        }
    }
    di.mean_dR_truth_m = di.n_check > 0 ? sum / di.n_check : std::nan("");
    out.intersections.push_back(std::move(di));
  }
  return out;
}

DemoRun simulate_and_run(const Scenario& scenario, const std::string& out_dir,
                         const std::function<void(const std::string&)>& progress) {
  DemoRun run;
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  say("simulating the scenario ...");
  run.mission = simulate_mission(scenario);
  const WrittenMission w = write_mission(run.mission, out_dir);
  say("wrote " + std::to_string(w.n_files) + " files (" + std::to_string(w.n_frames) + " frames) to " +
      out_dir);
  run.config = load_mission_config(w.config_path);
  run.logs = run_mission(run.config, [&](const StageLog& log) {
    say(fmt::format("stage {:<10} {:>8.3f} s, {} warning(s)", log.stage, log.wall_time_s,
                    log.warnings.size()));
  });
  run.results = collect_demo_results(run.mission, run.config);
  return run;
}

}  // namespace rangecal
