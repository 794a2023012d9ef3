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
#include "pipeline/steps/export_check.hpp"
#include "pipeline/steps/held_out_prediction.hpp"
#include "pipeline/steps/lens_selection.hpp"
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
  DltCamera dlt;                                     ///< DLT-11 + Argus profile (DLTdv, Argus, easyWand)
  bool opencv_refused = false, dlt_refused = false;  ///< not written (check_exports)
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

/// The export checks (pipeline/steps/export_check.hpp) into the record and the camera's warnings;
/// returns the warnings.
std::vector<std::string> check_exports(CameraCalibration* cc) {
  const ExportCheck x = check_exports(cc->opencv, cc->dlt);
  CalibrateCameraRecord& rec = cc->record;
  rec.opencv_fit_max_px = x.opencv_fit_max_px;
  rec.opencv_undistort_max_px = x.opencv_undistort_max_px;
  rec.dlt_only_rms_px = x.dlt_only_rms_px;
  rec.dlt_only_max_px = x.dlt_only_max_px;
  rec.dlt_profile_max_px = x.dlt_profile_max_px;
  rec.exports_refused = x.refused;
  cc->opencv_refused = x.opencv_refused, cc->dlt_refused = x.dlt_refused;
  cc->warnings.insert(cc->warnings.end(), x.warnings.begin(), x.warnings.end());
  return x.warnings;
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
NetworkOptions network_options(const GnssConfig& gnss, const CalibrateConfig& calibrate, bool white_only) {
  NetworkOptions options;
  options.ppk_error = gnss.error_model;
  options.estimate_ppk_error = gnss.estimate_error_model;
  options.estimate_image_sigma = calibrate.estimate_image_sigma;
  options.image_time_correlation = calibrate.image_time_correlation;
  options.estimate_white_only = white_only;
  return options;
}

NetworkSolution solve_network(const NetworkProblem& n, const LampTrack& track, const GnssConfig& gnss,
                              const CalibrateConfig& calibrate, bool white_only = false) {
  NetworkOptions options = network_options(gnss, calibrate, white_only);
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

/// A number of a method's details; NaN when absent or not a number (a NaN is written as null).
double details_number(const nlohmann::json& details, const char* key) {
  return details.is_object() && details.contains(key) && details[key].is_number() ? details[key].get<double>()
                                                                                  : std::nan("");
}

/// The guard's last check (docs/optimisation.md "The guarded model"): with a Gauss–Markov model it
/// estimated, the network's cameras must agree with the per-camera solutions they started from —
/// f and the centre within kConsistentSigma of the per-camera σ, scaled by that fit's variance factor
/// where it exceeds 1. A model that moves them farther bends the cameras to the fixes' error model
/// rather than the images (on a real flight: every f 0.5–1.5 % short, one 36σ from its bundle).
/// Returns what disagrees; empty when the model is white, given, or consistent.
constexpr double kConsistentSigma = 5;

std::vector<std::string> inconsistent_cameras(const NetworkResult& r, const PerCameraPass& pass) {
  std::vector<std::string> out;
  if (!r.ppk_estimate || !r.ppk_error.correlated()) return out;
  for (std::size_t c = 0; c < pass.done.size() && c < r.cameras.size(); ++c) {
    const CalibrationResult& alone = pass.done[c].second.main;
    const CalibrationResult& net = r.cameras[c].calibration;
    const double vf = details_number(alone.details, "variance_factor");
    const double scale = std::sqrt(std::isfinite(vf) ? std::max(1.0, vf) : 1.0);
    for (CameraParameter p :
         {CameraParameter::f, kCenterParameters[0], kCenterParameters[1], kCenterParameters[2]}) {
      const double sd = alone.sigma(p) * scale;
      if (!(sd > 0)) continue;
      const double z = std::abs(parameter_value(net.camera, p, alone.camera) -
                                parameter_value(alone.camera, p, alone.camera)) /
                       sd;
      if (z > kConsistentSigma)
        out.push_back(pass.done[c].first + " " + parameter_name(p) + " moved " + format_number("%.1f", z) +
                      "σ from its per-camera bundle");
    }
  }
  return out;
}

/// The held-out check of a Gauss–Markov model the network estimated (docs/optimisation.md "Held-out
/// blocks"): the estimated family and the white family each calibrate on alternate blocks and predict
/// the others. The white family replaces the estimate when the estimate's σ fails on the held-out
/// epochs (z rms above kHeldOutZ) and the white family predicts them clearly better (clearly_better:
/// a held-out predictive density 10× the estimate's). Both are needed. A score merely lower is no
/// evidence: on one draw of the demo's 26.6-s record the white family scored 0.011 lower over 66
/// epochs (a density ratio of 1.4) with σ 1.4× too small (z rms 1.42), and switching to it stated
/// check-pole σ of 0.37 cm for an error of 1.31 cm. Nor is a density ratio alone: the held-out
/// epochs' errors are correlated in time, so n·Δscore overstates the evidence — on another draw the
/// white family's n·Δscore was 44 with its σ too small (z rms 1.29, the estimate's 0.79), and
/// switching to it stated 0.37 cm for an error of 0.95 cm. Returns the reason to switch, or empty;
/// `record` receives the scores.
constexpr double kHeldOutZ = 1.25;

/// The held-out blocks' options for a mission whose network solved to `r`: its PPK outliers not scored.
HeldOutOptions held_out_options(const NetworkResult& r) {
  HeldOutOptions o;
  o.not_scored.resize(r.points.size());
  for (std::size_t k = 0; k < r.points.size(); ++k) o.not_scored[k] = r.points[k].ppk_outlier;
  return o;
}

std::string held_out_check(const NetworkProblem& n, const NetworkResult& r, const GnssConfig& gnss,
                           const CalibrateConfig& calibrate, nlohmann::json* record) {
  if (!r.ppk_estimate || !r.ppk_error.correlated()) return {};
  const std::vector<HeldOutScore> scores =
      score_held_out_blocks(n.cameras, n.points, n.observations,
                            {{"estimated", network_options(gnss, calibrate, false), {}},
                             {"white", network_options(gnss, calibrate, true), {}}},
                            held_out_options(r));
  *record = held_out_scores_json(scores);
  const HeldOutScore &estimated = scores[0], &white = scores[1];
  if (!estimated.scored || estimated.z_rms <= kHeldOutZ || !clearly_better(white, estimated)) return {};
  return "held-out blocks: the white model predicts them better (rms " +
         format_number("%.1f", 100 * white.rms_m) + " cm, z rms " + format_number("%.2f", white.z_rms) +
         ", against the estimated model's " + format_number("%.1f", 100 * estimated.rms_m) + " cm, z rms " +
         format_number("%.2f", estimated.z_rms) + ", over " + std::to_string(estimated.epochs) + " epochs)";
}

/// Each camera's lens set chosen by significance and the rim under the family the guard kept
/// (pipeline/steps/lens_selection.hpp): the chosen free sets replace the problem's. True when a
/// camera gained a parameter (the network is then to be solved again). A camera with its own free
/// set (cameras[i].free) keeps it as given.
bool select_lenses(const MissionConfig& cfg, bool white_only, const NetworkResult& r, NetworkProblem* n,
                   PerCameraPass* pass) {
  if (cfg.calibrate.free_candidates.empty()) return false;
  std::vector<std::string> ids;
  std::vector<bool> as_given;
  for (const auto& done : pass->done) {
    ids.push_back(done.first);
    const auto cam = std::find_if(cfg.cameras.begin(), cfg.cameras.end(),
                                  [&](const CameraConfig& c) { return c.id == done.first; });
    as_given.push_back(cam != cfg.cameras.end() && !cam->free.empty());
  }
  const LensSelection s = select_lens_parameters(
      n->cameras, n->points, n->observations, network_options(cfg.gnss, cfg.calibrate, white_only),
      cfg.calibrate.free_candidates, ids, held_out_options(r), as_given);
  pass->record.lens_selection = lens_selection_json(s, cfg.calibrate.free_candidates, ids);
  const bool changed = std::any_of(s.added.begin(), s.added.end(), [](const auto& a) { return !a.empty(); });
  if (changed) n->cameras = s.cameras;
  return changed;
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
    // The exports are the network's camera's, checked again (the method times stay those of the
    // per-camera pass, docs/outputs.md).
    cc.record = pass->record.cameras[id];
    for (const std::string& w : check_exports(&cc)) pass->warnings.push_back(id + ": " + w);
    pass->record.cameras[id] = cc.record;
    record_fit(net, &pass->record.cameras[id]);
    pass->record.cameras[id].warnings = warning_codes(r.cameras[c].warnings);
    for (const std::string& w : net.warnings) pass->warnings.push_back(id + ": " + w);
  }
  for (const std::string& w : r.warnings) pass->warnings.push_back("network: " + w);
  pass->record.network = statistics;
}

void write_camera_calibration(const MissionConfig& cfg, const std::string& id, const CameraCalibration& cc) {
  write_calibration_json(camera_output(cfg, id, kCalibrationJson), cc.main);
  // An export that cannot reproduce the camera is not written (check_exports).
  if (!cc.opencv_refused) write_opencv_camera_yml(camera_output(cfg, id, kCameraOpencvYml), cc.opencv);
  // One camera per file, numbered 1: `paste -d, cam1/dlt_coefficients.csv cam2/…` gives DLTdv's
  // multi-camera file (docs/outputs.md).
  if (!cc.dlt_refused) {
    write_file_atomic(camera_output(cfg, id, kDltCoefficientsCsv), dlt_coefficients_csv({cc.dlt}));
    write_file_atomic(camera_output(cfg, id, kArgusProfileTxt), argus_profile_txt({cc.dlt}));
  }
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

/// A variance factor χ²/dof above this says the noise model is wrong by more than √3 in σ: every σ
/// the fit states is too small by about √(χ²/dof) (docs/reliability.md "Run outcome").
constexpr double kDegradedVarianceFactor = 3;
/// More than this share of the PPK fixes dropped by the outlier test says the test, not the fixes,
/// is wrong (the image σ it weighs the rays by too small, or the model).
constexpr double kDegradedPpkOutlierShare = 0.1;

/// The estimate's guard refusal and what it says of the fixes, as a warning.
void add_guard_warning(const NetworkResult& r, std::vector<std::string>* warnings) {
  if (!r.ppk_estimate || r.ppk_estimate->guard_reasons.empty()) return;
  std::string why;
  for (const std::string& g : r.ppk_estimate->guard_reasons) why += (why.empty() ? "" : "; ") + g;
  warnings->push_back("network: the Gauss–Markov PPK error model estimated from the mission was refused (" +
                      why +
                      "): the fixes are weighed white, their scale estimated (docs/optimisation.md \"The "
                      "guarded model\")");
}

/// What the stage delivered but a user should look at before trusting (docs/reliability.md "Run
/// outcome").
std::vector<std::string> calibrate_degradations(const PerCameraPass& pass,
                                                const std::optional<NetworkSolution>& solution) {
  std::vector<std::string> out;
  const auto variance_factor = [&](const std::string& who, double vf) {
    if (vf > kDegradedVarianceFactor)
      out.push_back(who + " variance factor " + format_number("%.3g", vf) + ": the residuals are " +
                    format_number("%.2g", std::sqrt(vf)) +
                    " times the noise model's and every σ stated is too small by about that");
  };
  if (solution) {
    const NetworkResult& r = solution->result;
    variance_factor("network", r.statistics.variance_factor);
    if (r.ppk_estimate)
      for (const std::string& b : r.ppk_estimate->on_bound)
        out.push_back("network: the estimated " + b + ": the mission does not determine it");
    int fixes = 0;
    for (const NetworkPointResult& p : r.points) fixes += p.prior_used || p.ppk_outlier ? 1 : 0;
    const auto dropped = static_cast<double>(r.statistics.ppk_outliers.size());
    if (fixes > 0 && dropped > kDegradedPpkOutlierShare * fixes)
      out.push_back("network: " + format_number("%.0f", 100 * dropped / fixes) +
                    " % of the PPK fixes dropped as outliers");
  } else {
    for (const auto& [id, cc] : pass.done)
      variance_factor(id + " " + cc.main.method, details_number(cc.main.details, "variance_factor"));
  }
  for (const auto& [id, rec] : pass.record.cameras)
    for (const std::string& e : rec.exports_refused) out.push_back("camera " + id + ": not written: " + e);
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
      solution = solve_network(n, track, cfg.gnss, cfg.calibrate);
      std::vector<std::string> inconsistent = inconsistent_cameras(solution->result, pass);
      if (inconsistent.empty()) {
        const std::string held_out =
            held_out_check(n, solution->result, cfg.gnss, cfg.calibrate, &pass.record.held_out);
        if (!held_out.empty()) inconsistent.push_back(held_out);
      }
      const bool white_only = !inconsistent.empty();
      // The guard's fallback: the white family, image σ still estimated; the reasons stay with it.
      if (white_only) solution = solve_network(n, track, cfg.gnss, cfg.calibrate, white_only);
      if (select_lenses(cfg, white_only, solution->result, &n, &pass))
        solution = solve_network(n, track, cfg.gnss, cfg.calibrate, white_only);
      if (white_only) {
        std::vector<std::string>& why = solution->result.ppk_estimate->guard_reasons;
        why.insert(why.end(), inconsistent.begin(), inconsistent.end());
      }
      add_guard_warning(solution->result, &pass.warnings);
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
  log.degradations = calibrate_degradations(pass, solution);
  if (cfg.run.fail_on_degraded)
    for (const std::string& d : log.degradations)
      log.shortfalls.push_back(d + " (run.fail_on_degraded is true)");
  return log;
}

}  // namespace rangecal
