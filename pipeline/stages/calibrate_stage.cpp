#include "pipeline/stages/calibrate_stage.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "config/atomic_file.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "optim/network/network_adjustment.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/lamp_track_adjusted_csv.hpp"
#include "pipeline/io/method_details_json.hpp"
#include "pipeline/io/methods_csv.hpp"
#include "pipeline/io/network_json.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/residuals_csv.hpp"
#include "pipeline/steps/calibration_methods.hpp"
#include "pipeline/steps/calibration_problem.hpp"
#include "pipeline/steps/network_problem.hpp"
#include "vision/camera/dlt_export.hpp"
#include "vision/camera/opencv_camera_export.hpp"

namespace rangecal {
namespace {

/// Everything the stage computes for one camera, before anything is written.
struct CameraCalibration {
  CalibrationResult main;
  std::vector<CalibrationResult> compared;  ///< the `compare` methods that succeeded, config order
  OpenCvCamera opencv;
  DltCamera dlt;  ///< DLT-11 + Argus profile (DLTdv, Argus, easyWand)
  std::vector<ResidualRow> residuals;
  nlohmann::json counts;
  std::vector<std::string> warnings;  ///< without the camera id prefix
};

/// One row per observation of the problem: lamp pairs, then control poles.
std::vector<ResidualRow> residual_rows(const CalibrationProblem& problem,
                                       const std::vector<Correspondence>& pairs, const CalibrationResult& r) {
  const auto res = reprojection_residuals(r.camera, problem.observations, r.clock_offset_s);
  std::vector<bool> rejected(problem.observations.size(), false);
  for (std::size_t i : r.rejected)
    if (i < rejected.size()) rejected[i] = true;
  std::vector<ResidualRow> rows;
  for (std::size_t i = 0; i < problem.observations.size(); ++i) {
    ResidualRow row;
    const bool lamp = i < pairs.size();
    row.kind = lamp ? ResidualRow::Kind::lamp : ResidualRow::Kind::control;
    if (lamp)
      row.utc = pairs[i].utc;
    else
      row.id = problem.control_pole_ids[i - pairs.size()];
    row.enu = problem.observations[i].world;
    row.uv = problem.observations[i].pixel;
    if (res[i].allFinite()) row.d_px = res[i];
    row.used = !rejected[i];
    rows.push_back(row);
  }
  return rows;
}

/// The configured method, then every `compare` method (a compared method that fails is a
/// warning). Throws the configured method's rangecal::Error.
CameraCalibration calibrate_one_camera(const CalibrateConfig& calibrate, const CalibrationProblem& problem,
                                       const std::vector<Correspondence>& pairs) {
  CameraCalibration cc;
  cc.main = calibrate_camera(calibrate.method, problem);
  cc.counts["pairs"] = pairs.size();
  cc.counts["control_poles"] = problem.observations.size() - pairs.size();
  if (pairs.empty())
    cc.warnings.push_back("no lamp pairs; calibrated from its " +
                          std::to_string(problem.observations.size()) +
                          " control poles alone (seed 002's baseline setting, far fewer points)");
  cc.opencv = fit_opencv_camera(cc.main.camera);
  if (std::max(cc.opencv.fit_max_px, cc.opencv.undistort_max_px) > 0.01)
    cc.warnings.push_back("OpenCV model reproduces rangecal only to " + std::to_string(cc.opencv.fit_max_px) +
                          " px (cv::projectPoints) and " + std::to_string(cc.opencv.undistort_max_px) +
                          " px (cv::undistortPoints, default iterations)");
  cc.dlt = dlt_camera(cc.main.camera);
  if (std::max(cc.dlt.profile_max_px, cc.dlt.undistort_max_px) > 0.05)
    cc.warnings.push_back("DLT-11 + Argus profile reproduce rangecal only to " +
                          std::to_string(std::max(cc.dlt.profile_max_px, cc.dlt.undistort_max_px)) + " px");
  cc.residuals = residual_rows(problem, pairs, cc.main);
  nlohmann::json times;
  times[cc.main.method] = std::round(cc.main.wall_time_s * 1e4) / 1e4;
  for (const std::string& m : calibrate.compare) {
    if (m == calibrate.method) continue;
    try {
      cc.compared.push_back(calibrate_camera(m, problem));
      times[m] = std::round(cc.compared.back().wall_time_s * 1e4) / 1e4;
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::calibration) throw;
      cc.warnings.push_back("compare method " + m + " failed: " + e.what());
    }
  }
  cc.counts["method"] = cc.main.method;
  cc.counts["rms_px"] = cc.main.reprojection.rms_px;
  cc.counts["n_used"] = cc.main.reprojection.n_used;
  cc.counts["n_rejected"] = cc.main.reprojection.n_rejected;
  cc.counts["opencv_fit_max_px"] = cc.opencv.fit_max_px;
  cc.counts["opencv_undistort_max_px"] = cc.opencv.undistort_max_px;
  cc.counts["dlt_only_rms_px"] = cc.dlt.dlt_only_rms_px;
  cc.counts["dlt_only_max_px"] = cc.dlt.dlt_only_max_px;
  cc.counts["dlt_profile_max_px"] = std::max(cc.dlt.profile_max_px, cc.dlt.undistort_max_px);
  cc.counts["method_time_s"] = times;
  for (const auto& w : cc.main.warnings) cc.warnings.push_back(w);
  return cc;
}

void write_camera_calibration(const MissionConfig& cfg, const std::string& id, const CameraCalibration& cc) {
  write_calibration_json(camera_output(cfg, id, kCalibrationJson), cc.main);
  write_opencv_camera_yml(camera_output(cfg, id, kCameraOpencvYml), cc.opencv);
  // One camera per file, numbered 1: `paste -d, cam1/dlt_coefficients.csv cam2/…` gives DLTdv's
  // multi-camera file (docs/outputs.md).
  write_file_atomic(camera_output(cfg, id, kDltCoefficientsCsv), dlt_coefficients_csv({cc.dlt}));
  write_file_atomic(camera_output(cfg, id, kArgusProfileTxt), argus_profile_txt({cc.dlt}));
  write_residuals_csv(camera_output(cfg, id, kResidualsCsv), cc.residuals);
  // Each compared method's full result, so any method's cameras can be used downstream (e.g. the
  // demo's intersection with Tsai beside the bundle, seed 002 Table 4).
  for (const CalibrationResult& r : cc.compared)
    write_calibration_json(camera_output(cfg, id, compare_calibration_json(r.method)), r);
  if (!cfg.calibrate.compare.empty()) {
    std::vector<MethodRow> rows{method_row(cc.main)};
    for (const CalibrationResult& r : cc.compared) rows.push_back(method_row(r));
    write_file_atomic(camera_output(cfg, id, kMethodsCsv), format_methods_csv(rows));
  }
}

/// One camera's inputs kept for the network.
struct CameraInputs {
  std::string id;
  CalibrationProblem problem;
  std::vector<Correspondence> pairs;
};

/// The lamp track the network keys pairs to (empty, with a warning, when the gnss stage has not
/// written it).
LampTrack network_track(const MissionConfig& cfg, bool warn, StageLog* log) {
  if (std::filesystem::exists(lamp_track_path(cfg))) return read_lamp_track_csv(lamp_track_path(cfg));
  if (warn)
    log->warnings.push_back(
        "network: no " + lamp_track_path(cfg) +
        ": pairs cannot be keyed to epochs, every camera is calibrated from its own pairs");
  return {};
}

/// The calibrated cameras' problems joined through their shared epochs, each starting from its
/// per-camera bundle result.
NetworkProblem build_network(const MissionConfig& cfg, const std::vector<CameraInputs>& inputs,
                             const std::vector<std::pair<std::string, CameraCalibration>>& done,
                             const LampTrack& track) {
  std::vector<NetworkCameraInput> in;
  for (const auto& [id, cc] : done)
    for (const CameraInputs& ci : inputs)
      if (ci.id == id) in.push_back({&ci.problem, &ci.pairs, cc.main.camera, cc.main.clock_offset_s});
  return make_network_problem(in, track, cfg.align.max_frame_offset_s);
}

/// Method `network` (docs/optimisation.md "Network bundle"): the cameras calibrated by the
/// per-camera bundle (kept as the compared `bundle`) start one joint adjustment through their
/// shared lamp-track epochs; each camera's result is replaced by its network result, and
/// network.json and gnss/lamp_track_adjusted.csv are written.
void run_network(const MissionConfig& cfg, const std::vector<CameraInputs>& inputs, const LampTrack& track,
                 const NetworkProblem& n, std::vector<std::pair<std::string, CameraCalibration>>* done,
                 StageLog* log) {
  NetworkOptions options;
  // The report sets the flight volume's intersection σ beside this floor (docs/accuracy_analysis.md
  // "Datum floor"); the benchmarked network_adjust leaves it out by default.
  options.datum_floor_image_factor = kDatumFloorImageFactor;
  const NetworkResult r = network_adjust(n.cameras, n.points, n.observations, options);
  std::vector<std::string> utc(n.points.size());
  for (std::size_t k = 0; k < n.points.size(); ++k)
    if (n.epoch_of_point[k] >= 0)
      utc[k] = format_iso8601_utc(track.epochs[static_cast<std::size_t>(n.epoch_of_point[k])].utc);
  for (std::size_t c = 0; c < done->size(); ++c) {
    auto& [id, cc] = (*done)[c];
    CalibrationResult net = r.cameras[c].calibration;
    net.camera.id = id;
    net.details = bundle_details_json(r.cameras[c].details);
    net.details["network"] = network_statistics_json(r, utc);
    net.covariance = 0.5 * (net.covariance + net.covariance.transpose()).eval();
    // Map the network's rejected list (its observations of this camera) onto the problem's order.
    cc.compared.erase(std::remove_if(cc.compared.begin(), cc.compared.end(),
                                     [](const CalibrationResult& x) { return x.method == "network"; }),
                      cc.compared.end());
    cc.compared.insert(cc.compared.begin(), cc.main);
    net.site_origin = cfg.origin;
    cc.main = net;
    cc.opencv = fit_opencv_camera(cc.main.camera);
    cc.dlt = dlt_camera(cc.main.camera);
    for (const CameraInputs& ci : inputs)
      if (ci.id == id) cc.residuals = residual_rows(ci.problem, ci.pairs, cc.main);
    log->counts[id]["method"] = "network";
    log->counts[id]["rms_px"] = net.reprojection.rms_px;
    log->counts[id]["n_used"] = net.reprojection.n_used;
    log->counts[id]["n_rejected"] = net.reprojection.n_rejected;
    for (const std::string& w : net.warnings) log->warnings.push_back(id + ": " + w);
  }
  for (const std::string& w : r.warnings) log->warnings.push_back("network: " + w);
  log->counts["network"] = network_statistics_json(r, utc);
  write_network_json(mission_output(cfg, kNetworkJson), network_json(r, utc));
  if (!track.epochs.empty())
    write_file_atomic(mission_output(cfg, kLampTrackAdjustedCsv),
                      format_lamp_track_adjusted_csv(track, r, n.epoch_of_point));
}

}  // namespace

StageLog run_calibrate_stage(const MissionConfig& cfg) {
  StageLog log;
  log.stage = "calibrate";
  std::vector<std::pair<std::string, CameraCalibration>> done;
  std::vector<CameraInputs> inputs;
  // Without an explicit method: the per-camera bundle, then the network when the cameras share
  // epochs (docs/config.md "Default method").
  const bool automatic = cfg.calibrate.method.empty();
  const bool network = automatic || cfg.calibrate.method == "network";
  CalibrateConfig per_camera = cfg.calibrate;
  if (network) per_camera.method = "bundle";  // the network's start, kept as the compared bundle
  std::string last_failure, last_failed_file;
  for (const CameraConfig& cam : cfg.cameras) {
    const std::string corr_path = camera_output(cfg, cam.id, kCorrespondencesCsv);
    if (!std::filesystem::exists(corr_path))
      throw_input_error(corr_path, 0, "",
                        "missing; run the detect stage first (rangecal detect CONFIG), or "
                        "write the point pairs there yourself (docs/formats.md)");
    const std::vector<Correspondence> pairs = read_correspondences_csv(corr_path);
    const CalibrationProblem problem =
        make_calibration_problem(cam, cfg.calibrate, pairs, read_control_pole_views(cfg, cam));
    try {
      CameraCalibration cc = calibrate_one_camera(per_camera, problem, pairs);
      if (network) inputs.push_back({cam.id, problem, pairs});
      // Every calibration.json names the ENU frame its pose is in, so it stands alone.
      cc.main.site_origin = cfg.origin;
      for (CalibrationResult& r : cc.compared) r.site_origin = cfg.origin;
      log.counts[cam.id] = cc.counts;
      for (const std::string& w : cc.warnings) log.warnings.push_back(cam.id + ": " + w);
      done.emplace_back(cam.id, std::move(cc));
    } catch (const Error& e) {
      // One camera that cannot be calibrated must not stop the others: warn and go on.
      if (e.kind() != ErrorKind::calibration) throw;
      log.warnings.push_back(cam.id + ": calibration from " + corr_path + " failed: " + e.what());
      last_failure = cam.id + ": " + e.what();
      last_failed_file = corr_path;
      log.counts[cam.id] = {{"pairs", pairs.size()},
                            {"control_poles", problem.observations.size() - pairs.size()},
                            {"failed", e.what()}};
    }
  }
  if (done.empty())
    throw Error(ErrorKind::calibration, last_failed_file, 0, "calibrate",
                cfg.cameras.empty() ? "no cameras in the config"
                                    : "no camera could be calibrated (" + last_failure + ")");
  if (network) {
    const LampTrack track = network_track(cfg, !automatic, &log);
    const NetworkProblem n = build_network(cfg, inputs, done, track);
    const std::size_t shared = shared_epoch_count(n);
    if (automatic) {
      const bool use = shared > 0;
      log.counts["method_choice"] = {
          {"method", use ? "network" : "bundle"},
          {"shared_epochs", shared},
          {"why", use ? "default: " + std::to_string(shared) + " epochs seen by two or more cameras"
                      : "default: no epoch seen by two or more calibrated cameras, each camera by bundle"}};
      if (use) run_network(cfg, inputs, track, n, &done, &log);
    } else {
      run_network(cfg, inputs, track, n, &done, &log);
    }
  }
  for (const auto& [id, cc] : done) write_camera_calibration(cfg, id, cc);
  return log;
}

}  // namespace rangecal
