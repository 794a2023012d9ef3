#include "pipeline/stages/trajectory_stage.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/json_view.hpp"
#include "config/number_format.hpp"
#include "gnss/geodesy/local_enu.hpp"
#include "pipeline/io/align_record.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/imported_calibration.hpp"
#include "pipeline/io/network_json.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/trajectory_csv.hpp"
#include "pipeline/mission/stage_options.hpp"
#include "pipeline/report/trajectory_json.hpp"
#include "pipeline/stages/stage_inputs.hpp"
#include "pipeline/steps/camera_clock.hpp"
#include "pipeline/steps/intersection.hpp"
#include "vision/triangulation/trajectory_smoother.hpp"

namespace rangecal {

namespace {

bool any_target_track(const MissionConfig& cfg) {
  for (const CameraConfig& cam : cfg.cameras)
    if (cam.target_track) return true;
  return !cfg.trajectory.imported_cameras.empty();
}

// run.json's align record (the clocks the align stage estimated); empty without one.
AlignRecord read_align_record(const MissionConfig& cfg) {
  const std::string path = mission_output(cfg, kRunJson);
  if (!std::filesystem::exists(path)) return {};
  const nlohmann::json doc = parse_json_text(read_file_text(path), path, ErrorKind::input);
  if (!doc.is_object() || !doc.contains("stages") || !doc["stages"].is_object() ||
      !doc["stages"].contains("align") || !doc["stages"]["align"].is_object() ||
      !doc["stages"]["align"].contains("counts"))
    return {};
  return parse_align_record(doc["stages"]["align"]["counts"], path, "stages.align.counts");
}

// The labels of a camera's target track at their true times with their timing σ: UTC as given
// ("time_code"), or the camera's estimated clock applied ("calibration"; its σ at that time, wander
// included); a rolling shutter's readout (given, or the clock's) moves each label to its row's time.
std::vector<TimedLabel> timed_labels(const std::string& id, const TrackConfig& tc, int height_px,
                                     const CameraTrackInput& in, const AlignRecord& align,
                                     const std::string& run_json) {
  std::optional<ClockRecord> clock;
  UtcTime n0;
  if (tc.calibration_clock) {
    const auto it = align.cameras.find(id);
    if (it == align.cameras.end() || !it->second.clock)
      throw_input_error(run_json, 0, "stages.align.counts." + id + ".clock",
                        "camera " + id +
                            "'s target track is on its estimated clock, and the align stage has not "
                            "estimated one; run rangecal align CONFIG first");
    clock = it->second.clock;
    std::string why;
    const auto t = parse_iso8601_utc(clock->nominal_start_utc, &why);
    if (!t) throw_input_error(run_json, 0, "stages.align.counts." + id + ".clock.nominal_start_utc", why);
    n0 = *t;
  }
  const double readout = tc.readout_s != 0 ? tc.readout_s : clock ? clock->readout_s : 0.0;
  const double height = std::max(1, height_px - 1);
  std::vector<TimedLabel> labels;
  labels.reserve(in.track.points.size());
  for (std::size_t i = 0; i < in.track.points.size(); ++i) {
    const TrackedPoint& p = in.track.points[i];
    TimedLabel l;
    l.uv_px = p.uv;
    l.sigma_px = p.sigma_px.value_or(0);
    l.line = p.line;
    double shift_s = readout * (p.uv.y() / height - 0.5);
    double sd = tc.timing_sigma_s;
    if (clock) {
      const double since = 1e-9 * static_cast<double>(in.times[i].ns - n0.ns);
      shift_s += clock->offset_s + 1e-6 * clock->rate_ppm * since;
      const double c = clock_time_sd_s(clock->offset_sd_s, 1e-6 * clock->rate_sd_ppm, clock->mid_offset_sd_s,
                                       clock->span_s, since, clock->wander_sd_s);
      sd = std::sqrt(sd * sd + c * c);
    }
    l.t = UtcTime{in.times[i].ns + std::llround(shift_s * 1e9)};
    l.timing_sigma_s = sd;
    if (!labels.empty() && !(labels.back().t < l.t))
      throw_input_error(tc.file, p.line, "frame",
                        "the label's time does not follow the previous label's (frame times not increasing)");
    labels.push_back(l);
  }
  return labels;
}

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// run.json's counts of a camera's target labels: how many, their σ and where it came from, timing, clock.
nlohmann::json label_counts(const TrajectoryCamera& tc, const CameraTrackInput& in, const TrackConfig& track,
                            const std::string& label_sigma_source) {
  std::vector<double> timing;
  for (const TimedLabel& l : tc.labels) timing.push_back(l.timing_sigma_s);
  nlohmann::json pc;
  pc["labels"] = tc.labels.size();
  pc["outside_image"] = in.track.outside_image_lines.size();
  pc["label_sigma_px"] = tc.label_sigma_px;
  pc["labels_with_own_sigma"] =
      std::count_if(tc.labels.begin(), tc.labels.end(), [](const TimedLabel& l) { return l.sigma_px > 0; });
  pc["label_sigma_source"] = label_sigma_source;
  pc["timing_sigma_s_median"] = median(timing);
  pc["clock"] = track.calibration_clock ? "calibration" : "time_code";
  return pc;
}

// The labels' σ as estimated, into each camera's run.json counts: the σ used, the one given, its 1σ,
// the camera's share of the degrees of freedom and how it was set.
void record_label_sigma(const Trajectory& tr, const std::vector<TrajectoryCamera>& cameras,
                        nlohmann::json& per_camera, std::vector<std::string>& warnings) {
  const LabelVcResult& vc = tr.label_sigma;
  std::vector<std::string> kept;
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    nlohmann::json& pc = per_camera[cameras[c].id];
    const double given = cameras[c].label_sigma_px;
    pc["label_sigma_a_priori_px"] = given;
    pc["label_sigma_px"] = given * vc.sigma_scale[c];
    pc["label_sigma_scale"] = vc.sigma_scale[c];
    pc["label_sigma_sd_px"] = given * vc.sigma_scale_sd[c];
    pc["label_sigma_redundancy"] = vc.redundancy[c];
    pc["label_correlation"] = vc.correlation[c];
    pc["label_correlation_sd"] = vc.correlation_sd[c];
    pc["label_correlation_estimated"] = static_cast<bool>(vc.correlation_estimated[c]);
    const std::string source = pc["label_sigma_source"].get<std::string>();
    switch (vc.kind[c]) {
      case LabelScaleKind::own:
        pc["label_sigma_source"] = "estimated from the views (a priori: " + source + ")";
        break;
      case LabelScaleKind::common:
        pc["label_sigma_source"] =
            "estimated from the views, one scale with the cameras the geometry cannot tell apart (a "
            "priori: " +
            source + ")";
        break;
      case LabelScaleKind::as_given:
        pc["label_sigma_source"] = source + "; the views could not determine it";
        kept.push_back(cameras[c].id);
        break;
    }
  }
  if (!kept.empty()) {
    std::string ids;
    for (const std::string& id : kept) ids += (ids.empty() ? "" : ", ") + id;
    warnings.push_back("the labels' σ of " + ids +
                       " could not be estimated from the views (too few instants seen with other cameras, or "
                       "their σ hidden by others'): the σ given is used (docs/trajectory.md \"Label σ\")");
  }
}

}  // namespace

void require_trajectory_inputs(const MissionConfig& cfg) {
  if (!any_target_track(cfg))
    throw_input_error(
        cfg.config_path, 0, "cameras[].target_track",
        "no camera has a target track; the trajectory stage needs \"target_track\" (a 2-D "
        "track of the target with its frame times, docs/trajectory.md) for at least two cameras, or "
        "trajectory.imported_cameras");
}

StageLog run_trajectory_stage(const MissionConfig& cfg) {
  StageLog log;
  log.stage = "trajectory";
  nlohmann::json counts = nlohmann::json::object();
  if (!any_target_track(cfg)) {
    counts["skipped"] = "no camera has a \"target_track\"";
    log.counts = counts;
    return log;
  }
  const std::string run_json = mission_output(cfg, kRunJson);
  const AlignRecord align = read_align_record(cfg);
  const std::string network_path = mission_output(cfg, kNetworkJson);
  const std::map<std::string, double> image_sigma = read_network_image_sigma(network_path);

  std::vector<TrajectoryCamera> cameras;
  std::vector<std::vector<CameraParameter>> parameters;
  bool all_network = true;
  nlohmann::json per_camera = nlohmann::json::object();
  for (const CameraConfig& cc : cfg.cameras) {
    if (!cc.target_track) continue;
    const std::optional<CalibratedCamera> calibrated =
        read_calibrated_camera(cfg, cc.id, "the trajectory's σ counts its labels and timing", &log.warnings);
    if (!calibrated) continue;
    const CalibrationResult& cal = calibrated->result;
    const bool usable = calibrated->usable;
    TrajectoryCamera tc;
    tc.id = cc.id;
    tc.camera = cal.camera;
    tc.calibration = calibrated->covariance;
    const auto s = image_sigma.find(cc.id);
    const bool estimated = cal.method == "network" && s != image_sigma.end();
    tc.label_sigma_px = estimated ? s->second : cc.pixel_sigma.track_px;
    // The calibration's coverage, from the pairs it was given (a 64-px grid: 30 × 17 cells on a
    // 1920 × 1080 image; a label within a cell of a covered one counts as covered).
    if (const std::string pairs = camera_output(cfg, cc.id, kCorrespondencesCsv);
        std::filesystem::exists(pairs)) {
      std::vector<Eigen::Vector2d> seen;
      for (const Correspondence& c : read_correspondences_csv(pairs)) seen.push_back(c.uv);
      tc.coverage = ImageCoverage(seen, 64);
    }
    const CameraTrackInput in = read_track_input(*cc.target_track);
    tc.labels = timed_labels(cc.id, *cc.target_track, cc.sensor.height_px, in, align, run_json);
    per_camera[cc.id] =
        label_counts(tc, in, *cc.target_track,
                     estimated ? "network image variance component" : "pixel_sigma_px.track (stated)");
    all_network = all_network && cal.method == "network" && usable;
    parameters.push_back(tc.calibration.parameters);
    cameras.push_back(std::move(tc));
  }
  // The network's cross blocks are between the mission's own cameras, which come first; an imported
  // camera, calibrated apart from them, has none (estimate_trajectory: a missing block is independence).
  const std::size_t own = cameras.size();
  for (std::size_t k = 0; k < cfg.trajectory.imported_cameras.size(); ++k) {
    const ImportedCameraConfig& ic = cfg.trajectory.imported_cameras[k];
    // This mission's own calibration.json imported beside its camera would count that camera twice,
    // as if its errors were another's.
    if (!ic.rangecal_json.empty()) {
      const std::filesystem::path rel =
          std::filesystem::weakly_canonical(ic.rangecal_json)
              .lexically_relative(std::filesystem::weakly_canonical(cfg.output_dir));
      if (!rel.empty() && *rel.begin() != "..")
        throw_config_error(
            cfg.config_path,
            "trajectory.imported_cameras[" + std::to_string(k) + "].calibration.rangecal_json",
            "is this mission's own output: its camera is one of the mission's cameras; give its "
            "target track as that camera's cameras[].target_track");
    }
    const ImportedCalibration imported = read_imported_calibration(ic, cfg.origin);
    TrajectoryCamera tc;
    tc.id = ic.id;
    tc.camera = imported.camera;
    tc.calibration = imported.covariance;
    tc.model_sigma_px = imported.model_sigma_px;
    tc.label_sigma_px = ic.label_sigma_px;
    const CameraTrackInput in = read_track_input(ic.target_track);
    tc.labels = timed_labels(ic.id, ic.target_track, ic.sensor.height_px, in, align, run_json);
    nlohmann::json pc = label_counts(tc, in, ic.target_track, "label_sigma_px (stated)");
    nlohmann::json calibration;
    calibration["format"] = imported.format;
    calibration["file"] = imported.file;
    calibration["conversion_rms_px"] = imported.fit_rms_px;
    calibration["conversion_max_px"] = imported.fit_max_px;
    calibration["model_sigma_px"] = imported.model_sigma_px;
    pc["imported_calibration"] = calibration;
    per_camera[ic.id] = pc;
    if (imported.fit_max_px > 0.5)
      log.warnings.push_back("camera " + ic.id + ": rangecal's model reproduces " + imported.file + " to " +
                             format_number("%.2f", imported.fit_max_px) + " px at worst (rms " +
                             format_number("%.2f", imported.fit_rms_px) + " px, added to its labels' σ)");
    cameras.push_back(std::move(tc));
  }
  counts["cameras"] = per_camera;
  if (cameras.size() < 2) {
    log.shortfalls.push_back("the trajectory needs two calibrated cameras with a target track; " +
                             std::to_string(cameras.size()) + " has one (see the warnings)");
    log.counts = counts;
    return log;
  }
  CrossCovariances cross;
  if (all_network && own >= 2) {
    std::vector<std::string> ids;
    for (std::size_t c = 0; c < own; ++c) ids.push_back(cameras[c].id);
    cross = read_network_cross_covariances(network_path, ids, &parameters);
    if (cross.empty())
      log.warnings.push_back("the calibrations come from the network but " + network_path +
                             " does not hold their joint covariance: the trajectory's σ takes the cameras as "
                             "independent");
  }
  const double rate = cfg.trajectory.rate_hz > 0 ? cfg.trajectory.rate_hz : fastest_label_rate_hz(cameras);
  const std::vector<UtcTime> instants = trajectory_instants(cameras, rate);
  TrajectoryOptions options;
  options.extrapolation_sigma_px_per_px = cfg.trajectory.extrapolation_sigma_px_per_px;
  options.estimate_label_sigma = cfg.trajectory.estimate_label_sigma;
  Trajectory trajectory = estimate_trajectory(cameras, instants, cross.empty() ? nullptr : &cross, options);
  if (trajectory.label_sigma_estimated) {
    record_label_sigma(trajectory, cameras, per_camera, log.warnings);
    counts["cameras"] = per_camera;
    counts["label_sigma"] = {{"mode", "estimate"},
                             {"instants", trajectory.label_sigma.instants},
                             {"excluded", trajectory.label_sigma.excluded},
                             {"iterations", trajectory.label_sigma.iterations},
                             {"converged", trajectory.label_sigma.converged}};
  } else {
    counts["label_sigma"] = {{"mode", "stated"}};
  }
  if (cfg.trajectory.smooth) {
    const SmootherReport smoothed = smooth_trajectory(&trajectory);
    const SmootherOptions defaults;
    // No stretch of three instants: nothing was estimated (null, not a white model).
    const auto estimated = [&](double v) {
      return smoothed.stretches > 0 ? nlohmann::json(v) : nlohmann::json();
    };
    counts["smoothing"] = {{"model", "constant_acceleration"},
                           {"jerk_psd_m2_s5", estimated(smoothed.jerk_psd)},
                           {"label_error_tau_s", estimated(smoothed.label_tau_s)},
                           {"gap_steps", defaults.gap_steps},
                           {"stretches", smoothed.stretches},
                           {"instants", smoothed.smoothed}};
  } else {
    counts["smoothing"] = {{"model", "none"}};
  }
  for (const std::string& w : trajectory.warnings) log.warnings.push_back(w);
  LocalEnu site(cfg.origin);
  const std::string csv_path = mission_output(cfg, kTrajectoryCsv);
  const std::string csv = format_trajectory_csv(trajectory, site);

  counts["rate_hz"] = rate;
  counts["extrapolation_sigma_px_per_px"] = options.extrapolation_sigma_px_per_px;
  counts["instants"] = trajectory.instants;
  counts["triangulated"] = trajectory.points.size();
  counts["single_camera"] = trajectory.single_camera;
  counts["joint_covariance"] = !cross.empty();
  std::size_t inflated = 0;
  for (const TrajectoryPoint& p : trajectory.points) inflated += p.inflated ? 1 : 0;
  counts["inflated"] = inflated;
  std::size_t extrapolated = 0;
  for (const TrajectoryPoint& p : trajectory.points) extrapolated += p.extrapolated.empty() ? 0 : 1;
  counts["extrapolated"] = extrapolated;
  if (extrapolated > 0)
    log.warnings.push_back(std::to_string(extrapolated) + " of " + std::to_string(trajectory.points.size()) +
                           " instants rest on a camera's label outside the image region its calibration saw "
                           "(trajectory.csv column extrapolated): the lens model is extrapolated there and "
                           "their σ may not hold");
  // trajectory.json summarises the CSV as written (read back: the figures the report will show), and
  // run.json states the same medians.
  TrajectoryJsonContext context;
  context.origin = cfg.origin;
  context.rate_hz = rate;
  context.extrapolation_sigma_px_per_px = options.extrapolation_sigma_px_per_px;
  context.smoothing = counts["smoothing"];
  context.label_sigma = counts["label_sigma"];
  context.instants_tried = trajectory.instants;
  context.single_camera = trajectory.single_camera;
  context.joint_covariance = !cross.empty();
  context.cameras = per_camera;
  const nlohmann::json summary = trajectory_json(parse_trajectory_csv(csv, csv_path), context);
  for (const auto& [key, part] : {std::pair<const char*, const char*>{"median_sigma_m", "median"},
                                  {"median_sigma_labels_m", "labels_median"},
                                  {"median_sigma_timing_m", "timing_median"},
                                  {"median_sigma_calibration_m", "calibration_median"}})
    counts[key] = summary.contains("sigma_m") ? summary["sigma_m"][part] : nlohmann::json();
  write_file_atomic(csv_path, csv);
  write_file_atomic(mission_output(cfg, kTrajectoryJson), summary.dump(2) + "\n");
  log.counts = counts;
  if (trajectory.points.empty())
    log.shortfalls.push_back(
        "no instant of the target was seen by two calibrated cameras: trajectory.csv is empty");
  return log;
}

}  // namespace rangecal
