#include "pipeline/stages/gnss_stage.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "gnss/geodesy/local_enu.hpp"
#include "gnss/track/antenna_epochs.hpp"
#include "gnss/track/lever_arm.hpp"
#include "pipeline/io/gnss_record.hpp"
#include "pipeline/io/output_paths.hpp"

namespace rangecal {

ResolvedLeverArm resolve_lever_arm(const LeverArmConfig& cfg) {
  ResolvedLeverArm r;
  switch (cfg.kind) {
    case LeverArmConfig::Kind::body_frd:
      r.form = ResolvedLeverArm::Form::body_frd;
      r.source = "body_frd";
      r.body_frd_m = cfg.body_frd_m;
      break;
    case LeverArmConfig::Kind::vertical:
      r.form = ResolvedLeverArm::Form::vertical;
      r.source = "vertical";
      r.vertical_m = cfg.vertical_m;
      break;
    case LeverArmConfig::Kind::total_station: {
      const TotalStationOffset ts = read_total_station_csv(cfg.total_station_file);
      r.form = ResolvedLeverArm::Form::vertical;
      r.source = "total_station";
      r.vertical_m = ts.vertical_m;
      r.vertical_sd_m = ts.sd_m;
      r.sessions = static_cast<int>(ts.sessions.size());
      break;
    }
  }
  return r;
}

GnssRecord gnss_record(const LampTrackReport& rep, const std::vector<PosFile>& files,
                       const ResolvedLeverArm& lever) {
  GnssRecord r;
  for (const PosFile& f : files)
    r.pos_files.push_back({f.path, f.epochs.size(), to_string(f.header.time_system),
                           to_string(f.header.time_format), to_string(f.header.position_format),
                           f.header.has_velocity});
  r.epochs_read = rep.filter.read;
  r.epochs_kept = rep.track_epochs;
  r.dropped_quality = rep.filter.dropped_quality;
  r.dropped_quality_by_q = rep.filter.dropped_by_quality;
  r.read_by_q = rep.filter.read_by_quality;
  r.dropped_sd = rep.filter.dropped_sd;
  r.dropped_no_attitude = rep.dropped_no_attitude;
  for (const TimeGap& g : rep.gaps)
    r.gap_list.push_back(
        {format_iso8601_utc(g.from, 9), format_iso8601_utc(g.to, 9), std::round(g.duration_s() * 1e9) / 1e9});
  r.track_start = format_iso8601_utc(rep.track_start, 9);
  r.track_end = format_iso8601_utc(rep.track_end, 9);
  r.track_span_s = std::round(seconds_between(rep.track_start, rep.track_end) * 1e9) / 1e9;
  LeverArmRecord& la = r.lever_arm;
  la.source = lever.source;
  if (lever.form == ResolvedLeverArm::Form::body_frd) {
    la.body_frd_m = {lever.body_frd_m[0], lever.body_frd_m[1], lever.body_frd_m[2]};
    la.motion_max_mm_per_ms = rep.lever_motion_max_mm_per_ms;
    la.motion_rms_mm_per_ms = rep.lever_motion_rms_mm_per_ms;
  } else {
    la.vertical_m = lever.vertical_m;
    la.vertical_sd_m = lever.vertical_sd_m;
    la.sessions = lever.sessions;
    la.vertical_form_max_error_m = rep.vertical_form_max_error_m;
    la.vertical_form_epochs_over_5mm = rep.vertical_form_epochs_over_5mm;
  }
  return r;
}

AttitudeRecord attitude_record(const AttitudeFileReport& rep, const std::string& path) {
  AttitudeRecord a{path,
                   to_string(rep.kind),
                   rep.samples,
                   format_iso8601_utc(rep.utc_start, 9),
                   format_iso8601_utc(rep.utc_end, 9),
                   std::nullopt};
  if (!rep.log) return a;
  const AutopilotAttitudeReport& r = *rep.log;
  const BootTimeFit& f = r.fit;
  AutopilotLogRecord& l = a.log.emplace();
  l.file_bytes = r.file_bytes;
  l.truncated_bytes = r.truncated_bytes;
  l.attitude_message = r.attitude_message;
  l.attitude_time_field = r.attitude_time_field;
  l.attitude_messages = r.attitude_messages;
  l.attitude_invalid = r.attitude_invalid;
  l.attitude_not_increasing = r.attitude_not_increasing;
  l.gps_message = r.gps_message;
  l.gps_messages = r.gps_messages;
  l.gps_skipped = r.gps_skipped;
  l.gps_used = f.used;
  l.gps_rejected = f.rejected;
  l.gps_span_s = static_cast<double>(f.last_boot_us - f.first_boot_us) * 1e-6;
  l.boot_zero_utc = format_iso8601_utc(f.to_utc(0), 9);
  l.offset_ns = f.offset_ns;
  l.offset_ref_boot_us = f.ref_boot_us;
  l.drift_fitted = f.drift_fitted;
  l.drift_ppm = f.drift_ppm;
  l.residual_rms_us = f.residual_rms_us;
  l.residual_max_us = f.residual_max_us;
  l.reject_threshold_us = f.reject_threshold_us;
  l.gnss_lag_ms = r.gnss_lag_ms;
  l.gnss_lag_source = r.gnss_lag_given ? "attitude.gnss_lag_ms" : "default for " + r.format;
  return a;
}

StageLog run_gnss_stage(const MissionConfig& cfg) {
  LampTrackInputs in;
  if (cfg.gnss.pos_files.empty())
    throw_config_error(cfg.config_path, "gnss.pos_files", "at least one .pos file is needed");
  for (const std::string& p : cfg.gnss.pos_files) in.pos_files.push_back(read_rtklib_pos(p));
  AttitudeFileReport attitude_report;
  if (!cfg.attitude_file.empty()) {
    in.attitude = read_attitude_file(cfg.attitude_file, &attitude_report, cfg.attitude_gnss_lag_ms);
    if (cfg.attitude_gnss_lag_ms && !attitude_report.log)
      throw_config_error(cfg.config_path, "attitude.gnss_lag_ms",
                         "the attitude file is a CSV, whose times are UTC already: the GNSS receiver lag "
                         "applies to autopilot logs (PX4 ULog, ArduPilot DataFlash) only; remove the key");
  }
  if (cfg.lever_arm.kind == LeverArmConfig::Kind::body_frd && !in.attitude)
    throw_config_error(cfg.config_path, "lever_arm.body_frd_m",
                       "a body-frame lever arm needs attitude.file (or use lever_arm.vertical_m)");
  in.lever = resolve_lever_arm(cfg.lever_arm);
  in.origin = cfg.origin;
  in.filter.accept_quality = cfg.gnss.accept_quality;
  in.filter.max_sd_m = cfg.gnss.max_sd_m;
  in.filter.max_gap_s = cfg.gnss.max_gap_s;
  const LampTrackResult res = compute_lamp_track(in);
  write_lamp_track_csv(lamp_track_path(cfg), res.track);

  StageLog log;
  log.stage = "gnss";
  GnssRecord record = gnss_record(res.report, in.pos_files, in.lever);
  if (in.attitude) record.attitude = attitude_record(attitude_report, cfg.attitude_file);
  log.counts = gnss_record_json(record);
  log.warnings = res.report.warnings;
  if (attitude_report.log) {
    // What run.json's attitude counts hold, said once on the console too (docs/gnss.md).
    const AutopilotAttitudeReport& r = *attitude_report.log;
    if (r.truncated_bytes > 0)
      log.warnings.push_back(cfg.attitude_file + ": the log is truncated: its last " +
                             std::to_string(r.truncated_bytes) +
                             " byte(s) are an incomplete message and were not read");
    if (r.fit.rejected > 0)
      log.warnings.push_back(cfg.attitude_file + ": " + std::to_string(r.fit.rejected) + " of " +
                             std::to_string(r.fit.used + r.fit.rejected) + " " + r.gps_message +
                             " time pairs rejected as jumps from the boot-time -> UTC fit (threshold " +
                             std::to_string(static_cast<long long>(r.fit.reject_threshold_us)) + " us)");
  }
  return log;
}

}  // namespace rangecal
