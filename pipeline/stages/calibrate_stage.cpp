#include "pipeline/stages/calibrate_stage.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>

#include "config/atomic_file.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "optim/estimation/symmetric_part.hpp"
#include "optim/network/network_adjustment.hpp"
#include "pipeline/io/calibrate_record.hpp"
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
#include "pipeline/steps/covariance_under_model.hpp"
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
  CalibrateCameraRecord record;
  std::vector<std::string> warnings;  ///< without the camera id prefix
};

/// One camera's inputs: its lamp pairs and the problem made of them (kept for the network).
struct CameraInputs {
  std::string id;
  std::vector<Correspondence> pairs;
  CalibrationProblem problem;
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

/// cc.main's exports (OpenCV, DLT-11 + Argus profile) and its residual rows.
void derive_exports_and_residuals(const CameraInputs& in, CameraCalibration* cc) {
  cc->opencv = fit_opencv_camera(cc->main.camera);
  cc->dlt = dlt_camera(cc->main.camera);
  cc->residuals = residual_rows(in.problem, in.pairs, cc->main);
}

/// The record's method and reprojection statistics, from `r`.
void record_fit(const CalibrationResult& r, CalibrateCameraRecord* record) {
  record->method = r.method;
  record->rms_px = r.reprojection.rms_px;
  record->n_used = r.reprojection.n_used;
  record->n_rejected = r.reprojection.n_rejected;
}

/// The export checks: how far the OpenCV and DLT-11 + Argus profile exports reproduce the camera,
/// into the record, and a warning when beyond what their users can ignore.
void check_exports(CameraCalibration* cc) {
  CalibrateCameraRecord& rec = cc->record;
  rec.opencv_fit_max_px = cc->opencv.fit_max_px;
  rec.opencv_undistort_max_px = cc->opencv.undistort_max_px;
  rec.dlt_only_rms_px = cc->dlt.dlt_only_rms_px;
  rec.dlt_only_max_px = cc->dlt.dlt_only_max_px;
  rec.dlt_profile_max_px = std::max(cc->dlt.profile_max_px, cc->dlt.undistort_max_px);
  if (std::max(cc->opencv.fit_max_px, cc->opencv.undistort_max_px) > 0.01)
    cc->warnings.push_back("OpenCV model reproduces rangecal only to " +
                           std::to_string(cc->opencv.fit_max_px) + " px (cv::projectPoints) and " +
                           std::to_string(cc->opencv.undistort_max_px) +
                           " px (cv::undistortPoints, default iterations)");
  if (rec.dlt_profile_max_px > 0.05)
    cc->warnings.push_back("DLT-11 + Argus profile reproduce rangecal only to " +
                           std::to_string(rec.dlt_profile_max_px) + " px");
}

double wall_time_record(const CalibrationResult& r) {
  return std::round(r.wall_time_s * 1e4) / 1e4;
}

/// The configured method, then every `compare` method (a compared method that fails is a
/// warning). Throws the configured method's rangecal::Error.
CameraCalibration calibrate_one_camera(const CalibrateConfig& calibrate, const CameraInputs& in) {
  CameraCalibration cc;
  CalibrationRun main = run_calibration_method(calibrate.method, in.problem);
  cc.main = std::move(main.result);
  cc.record.warnings = warning_codes(main.warnings);
  cc.record.pairs = in.pairs.size();
  cc.record.control_poles = in.problem.observations.size() - in.pairs.size();
  if (in.pairs.empty())
    cc.warnings.push_back("no lamp pairs; calibrated from its " +
                          std::to_string(in.problem.observations.size()) +
                          " control poles alone (seed 002's baseline setting, far fewer points)");
  derive_exports_and_residuals(in, &cc);
  check_exports(&cc);
  cc.record.method_time_s[cc.main.method] = wall_time_record(cc.main);
  for (const std::string& m : calibrate.compare) {
    if (m == calibrate.method) continue;
    try {
      cc.compared.push_back(calibrate_camera(m, in.problem));
      cc.record.method_time_s[m] = wall_time_record(cc.compared.back());
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::calibration) throw;
      cc.warnings.push_back("compare method " + m + " failed: " + e.what());
    }
  }
  record_fit(cc.main, &cc.record);
  for (const auto& w : cc.main.warnings) cc.warnings.push_back(w);
  return cc;
}

/// The per-camera pass over the config's cameras: who was calibrated, from what, and the record
/// and warnings of every camera (one that cannot be calibrated is a warning; the others go on).
struct PerCameraPass {
  std::vector<std::pair<std::string, CameraCalibration>> done;  ///< calibrated, config order
  std::vector<CameraInputs> inputs;                             ///< of `done`, same order
  CalibrateRecord record;
  std::vector<std::string> warnings;
  std::string last_failure, last_failed_file;
};

/// Calibrates the camera read from `corr_path` into `pass`. Throws any rangecal::Error that is not
/// a calibration failure.
void calibrate_or_record_failure(const CalibrateConfig& per_camera, const GeodeticOrigin& origin,
                                 const std::string& corr_path, CameraInputs in, PerCameraPass* pass) {
  try {
    CameraCalibration cc = calibrate_one_camera(per_camera, in);
    // Every calibration.json names the ENU frame its pose is in, so it stands alone.
    cc.main.site_origin = origin;
    for (CalibrationResult& r : cc.compared) r.site_origin = origin;
    pass->record.cameras[in.id] = cc.record;
    for (const std::string& w : cc.warnings) pass->warnings.push_back(in.id + ": " + w);
    pass->done.emplace_back(in.id, std::move(cc));
    pass->inputs.push_back(std::move(in));
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::calibration) throw;
    pass->warnings.push_back(in.id + ": calibration from " + corr_path + " failed: " + e.what());
    pass->last_failure = in.id + ": " + e.what();
    pass->last_failed_file = corr_path;
    CalibrateCameraRecord& rec = pass->record.cameras[in.id];
    rec.pairs = in.pairs.size();
    rec.control_poles = in.problem.observations.size() - in.pairs.size();
    rec.failed = e.what();
  }
}

/// The lamp track the network keys pairs to (empty, with a warning, when the gnss stage has not
/// written it).
LampTrack read_network_track(const MissionConfig& cfg, bool warn, std::vector<std::string>* warnings) {
  if (std::filesystem::exists(lamp_track_path(cfg))) return read_lamp_track_csv(lamp_track_path(cfg));
  if (warn)
    warnings->push_back("network: no " + lamp_track_path(cfg) +
                        ": pairs cannot be keyed to epochs, every camera is calibrated from its own pairs");
  return {};
}

/// The calibrated cameras' problems joined through their shared epochs, each starting from its
/// per-camera bundle result.
NetworkProblem build_network(const PerCameraPass& pass, const LampTrack& track, double max_frame_offset_s) {
  std::vector<NetworkCameraInput> in;
  for (std::size_t c = 0; c < pass.done.size(); ++c) {
    const CameraInputs& ci = pass.inputs[c];
    const CalibrationResult& start = pass.done[c].second.main;
    in.push_back({&ci.problem, &ci.pairs, start.camera, start.clock_offset_s});
  }
  return make_network_problem(in, track, max_frame_offset_s);
}

/// The default rule (docs/config.md "Default method"): the network when an epoch is seen by two or
/// more calibrated cameras, else each camera by bundle.
MethodChoiceRecord choose_default_method(std::size_t shared) {
  const bool use = shared > 0;
  return {use ? "network" : "bundle", shared,
          use ? "default: " + std::to_string(shared) + " epochs seen by two or more cameras"
              : "default: no epoch seen by two or more calibrated cameras, each camera by bundle"};
}

/// The network's joint adjustment and the UTC of each of its points' epochs ("" for the others).
struct NetworkSolution {
  NetworkResult result;
  std::vector<std::string> epoch_utc;
};

/// Method `network` (docs/optimisation.md "Network bundle"): one joint adjustment of the cameras
/// through their shared lamp-track epochs.
NetworkSolution solve_network(const NetworkProblem& n, const LampTrack& track, const GnssConfig& gnss) {
  NetworkOptions options;
  options.ppk_error = gnss.error_model;
  options.estimate_ppk_error = gnss.estimate_error_model;
  // The report sets the flight volume's intersection σ beside this floor (docs/accuracy_analysis.md
  // "Datum floor"); the benchmarked network_adjust leaves it out by default.
  options.datum_floor_image_factor = kDatumFloorImageFactor;
  NetworkSolution s{network_adjust(n.cameras, n.points, n.observations, options), {}};
  s.epoch_utc.resize(n.points.size());
  for (std::size_t k = 0; k < n.points.size(); ++k)
    if (n.epoch_of_point[k] >= 0)
      s.epoch_utc[k] = format_iso8601_utc(track.epochs[static_cast<std::size_t>(n.epoch_of_point[k])].utc);
  return s;
}

/// Under a model the network estimated with a Gauss–Markov part, the per-camera bundle restates its
/// σ under it (docs/optimisation.md "σ under correlated PPK errors"): re-solved, the same
/// white-weighted estimate, the sandwich covariance under the estimate.
void restate_bundle_under(const NetworkResult& r, CameraInputs* in, CalibrationResult* bundle) {
  if (!r.ppk_estimate || !r.ppk_error.correlated() || bundle->method != "bundle") return;
  in->problem.ppk_error = r.ppk_error;
  CalibrationResult restated = run_calibration_method("bundle", in->problem).result;
  restated.camera.id = bundle->camera.id;
  restated.site_origin = bundle->site_origin;
  restated.wall_time_s = bundle->wall_time_s;
  *bundle = std::move(restated);
}

/// Under the same model, every other compared method's σ: the bundle's sandwich at that method's
/// own solution (pipeline/steps/covariance_under_model.hpp); its estimate stays.
void restate_compared_under(const NetworkResult& r, const CameraInputs& in,
                            std::vector<CalibrationResult>* compared) {
  if (!r.ppk_estimate || !r.ppk_error.correlated()) return;
  for (CalibrationResult& x : *compared)
    if (x.method != "bundle" && x.method != "network") restate_covariance_under(r.ppk_error, in.problem, &x);
}

/// Each camera's result replaced by its network result (the per-camera bundle kept first among the
/// compared), its exports and residuals redone, its record's fit and the warnings updated.
void adopt_network_results(const NetworkSolution& s, const GeodeticOrigin& origin, PerCameraPass* pass) {
  const NetworkResult& r = s.result;
  const nlohmann::json statistics = network_statistics_json(r, s.epoch_utc);
  for (std::size_t c = 0; c < pass->done.size(); ++c) {
    auto& [id, cc] = pass->done[c];
    CalibrationResult net = r.cameras[c].calibration;
    net.camera.id = id;
    net.details = bundle_details_json(r.cameras[c].details);
    net.details["network"] = statistics;
    net.covariance = symmetric_part(net.covariance);
    net.site_origin = origin;
    cc.compared.erase(std::remove_if(cc.compared.begin(), cc.compared.end(),
                                     [](const CalibrationResult& x) { return x.method == "network"; }),
                      cc.compared.end());
    restate_bundle_under(r, &pass->inputs[c], &cc.main);
    restate_compared_under(r, pass->inputs[c], &cc.compared);
    cc.compared.insert(cc.compared.begin(), cc.main);
    cc.main = net;
    // The network lists each camera's rejected observations in that camera's own order, the
    // problem's (make_network_problem adds them in it), as residual_rows reads them.
    derive_exports_and_residuals(pass->inputs[c], &cc);
    // The export fits and method times stay those of the per-camera pass (docs/outputs.md).
    record_fit(net, &pass->record.cameras[id]);
    pass->record.cameras[id].warnings = warning_codes(r.cameras[c].warnings);
    for (const std::string& w : net.warnings) pass->warnings.push_back(id + ": " + w);
  }
  for (const std::string& w : r.warnings) pass->warnings.push_back("network: " + w);
  pass->record.network = statistics;
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

/// network.json and, when the pairs were keyed to a track, gnss/lamp_track_adjusted.csv.
void write_network_outputs(const MissionConfig& cfg, const NetworkSolution& s, const LampTrack& track,
                           const NetworkProblem& n) {
  write_network_json(mission_output(cfg, kNetworkJson), network_json(s.result, s.epoch_utc));
  if (!track.epochs.empty())
    write_file_atomic(mission_output(cfg, kLampTrackAdjustedCsv),
                      format_lamp_track_adjusted_csv(track, s.result, n.epoch_of_point));
}

/// One camera's inputs, read: its correspondences.csv (which must exist) and control-pole picks.
CameraInputs read_camera_inputs(const MissionConfig& cfg, const CameraConfig& cam,
                                const std::string& corr_path) {
  if (!std::filesystem::exists(corr_path))
    throw_input_error(corr_path, 0, "",
                      "missing; run the detect stage first (rangecal detect CONFIG), or "
                      "write the point pairs there yourself (docs/formats.md)");
  CameraInputs in{cam.id, read_correspondences_csv(corr_path), {}};
  in.problem = make_calibration_problem(cam, cfg.calibrate, in.pairs, read_control_pole_views(cfg, cam));
  // The bundle states its σ under the model the network weighs by (docs/gnss.md "PPK error model").
  in.problem.ppk_error = cfg.gnss.error_model;
  return in;
}

/// What a complete mission needs but this pass lacks (docs/reliability.md "Run outcome"): every
/// configured camera calibrated and, under run.fail_on_poorly_determined, no parameter the
/// diagnostics call poorly determined (optim/bundle/bundle_diagnostics.hpp words it so).
std::vector<std::string> calibrate_shortfalls(const MissionConfig& cfg, const PerCameraPass& pass) {
  std::vector<std::string> out;
  for (const CameraConfig& cam : cfg.cameras) {
    const auto it = pass.record.cameras.find(cam.id);
    if (it != pass.record.cameras.end() && !it->second.failed.empty())
      out.push_back("camera " + cam.id + " not calibrated (from " +
                    camera_output(cfg, cam.id, kCorrespondencesCsv) + "): " + it->second.failed);
  }
  if (cfg.run.fail_on_poorly_determined)
    for (const auto& [id, cc] : pass.done)
      for (const std::string& w : cc.main.warnings)
        if (w.find(" is poorly determined: ") != std::string::npos)
          out.push_back("camera " + id + ": " + w + " (run.fail_on_poorly_determined is true)");
  return out;
}

}  // namespace

StageLog run_calibrate_stage(const MissionConfig& cfg) {
  // Without an explicit method: the per-camera bundle, then the network when the cameras share
  // epochs (docs/config.md "Default method").
  const bool automatic = cfg.calibrate.method.empty();
  const bool network = automatic || cfg.calibrate.method == "network";
  CalibrateConfig per_camera = cfg.calibrate;
  if (network) per_camera.method = "bundle";  // the network's start, kept as the compared bundle

  PerCameraPass pass;
  for (const CameraConfig& cam : cfg.cameras) {
    const std::string corr_path = camera_output(cfg, cam.id, kCorrespondencesCsv);
    calibrate_or_record_failure(per_camera, cfg.origin, corr_path, read_camera_inputs(cfg, cam, corr_path),
                                &pass);
  }
  if (pass.done.empty())
    throw Error(ErrorKind::calibration, pass.last_failed_file, 0, "calibrate",
                cfg.cameras.empty() ? "no cameras in the config"
                                    : "no camera could be calibrated (" + pass.last_failure + ")");

  std::optional<NetworkSolution> solution;
  LampTrack track;
  NetworkProblem n;
  if (network) {
    track = read_network_track(cfg, !automatic, &pass.warnings);
    n = build_network(pass, track, cfg.align.max_frame_offset_s);
    if (automatic) pass.record.method_choice = choose_default_method(shared_epoch_count(n));
    if (!automatic || pass.record.method_choice->method == "network") {
      solution = solve_network(n, track, cfg.gnss);
      adopt_network_results(*solution, cfg.origin, &pass);
    }
  }

  if (solution) write_network_outputs(cfg, *solution, track, n);
  for (const auto& [id, cc] : pass.done) write_camera_calibration(cfg, id, cc);
  StageLog log;
  log.stage = "calibrate";
  log.counts = calibrate_record_json(pass.record);
  log.warnings = std::move(pass.warnings);
  log.shortfalls = calibrate_shortfalls(cfg, pass);
  return log;
}

}  // namespace rangecal
