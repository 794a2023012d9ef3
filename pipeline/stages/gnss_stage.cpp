#include "pipeline/stages/gnss_stage.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/track/antenna_epochs.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "gnss/track/lever_arm.hpp"
#include "gnss/geodesy/local_enu.hpp"
#include "pipeline/io/output_paths.hpp"

namespace rangecal {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

std::string mm(double m) {
  return format_number("%.1f", m * 1e3) + " mm";
}

// The attitude must cover some of the GNSS epochs: a log of another flight (or one whose boot
// time was mapped to UTC wrongly) would otherwise only show as every epoch dropped, or silently
// unused in the vertical form.
void check_attitude_overlaps(const AttitudeSeries& att, const std::vector<AntennaEpoch>& epochs,
                             const std::vector<PosFile>& pos_files) {
  if (att.samples.empty() || epochs.empty()) return;
  const UtcTime a0 = att.samples.front().utc, a1 = att.samples.back().utc;
  const UtcTime g0 = epochs.front().utc, g1 = epochs.back().utc;
  if (a0 <= g1 && g0 <= a1) return;
  std::string files;
  for (const PosFile& f : pos_files) files += (files.empty() ? "" : ", ") + f.path;
  throw_input_error(att.path, 0, "utc",
                    "the attitude " + format_iso8601_utc(a0, 3) + " … " + format_iso8601_utc(a1, 3) +
                        " does not overlap the GNSS epochs " + format_iso8601_utc(g0, 3) + " … " +
                        format_iso8601_utc(g1, 3) + " of " + files +
                        ": the attitude log is of another flight, or its time is wrong");
}

}  // namespace

GnssStageResult compute_lamp_track(const GnssStageInputs& in) {
  const bool full = in.lever.form == ResolvedLeverArm::Form::body_frd;
  if (full && !in.attitude)
    throw Error(ErrorKind::usage, "", 0, "lever_arm.body_frd_m",
                "a body-frame lever arm needs the attitude (set attitude.file, or use lever_arm.vertical_m)");
  GnssStageResult res;
  GnssStageReport& rep = res.report;
  const LocalEnu site(in.origin);
  const std::vector<AntennaEpoch> kept =
      filter_epochs(merge_antenna_epochs(in.pos_files, site), in.filter, &rep.filter);
  if (in.attitude) check_attitude_overlaps(*in.attitude, kept, in.pos_files);

  res.track.epochs.reserve(kept.size());
  double max_tilt_deg = 0;
  for (const AntennaEpoch& a : kept) {
    std::optional<Attitude> att;
    if (in.attitude) att = interpolate_attitude(*in.attitude, a.utc, in.max_attitude_gap_s);
    LampEpoch e;
    e.utc = a.utc;
    e.quality = a.quality;
    // The lamp moves with the antenna; the lever's rotation rate (ω × lever, a few mm/s) is ignored.
    e.vel_enu = a.vel_enu;
    Eigen::Vector3d var = a.cov_enu.diagonal();
    if (full) {
      if (!att) {
        ++rep.dropped_no_attitude;
        continue;
      }
      e.enu = lamp_enu_full(a.enu, rotation_nb(*att), in.lever.body_frd_m);
    } else {
      e.enu = lamp_enu_vertical(a.enu, in.lever.vertical_m);
      var[2] += in.lever.vertical_sd_m * in.lever.vertical_sd_m;
      if (att) {
        const double err = vertical_form_error_m(rotation_nb(*att), in.lever.vertical_m);
        if (err > rep.vertical_form_max_error_m) {
          rep.vertical_form_max_error_m = err;
          // The body z axis tilts from the vertical by acos(cos roll · cos pitch).
          max_tilt_deg =
              std::acos(std::min(1.0, std::cos(att->roll_deg * kDeg) * std::cos(att->pitch_deg * kDeg))) /
              kDeg;
        }
        if (err > kVerticalFormWarnM) ++rep.vertical_form_epochs_over_5mm;
      }
    }
    e.sd_enu = var.cwiseMax(0.0).cwiseSqrt();
    res.track.epochs.push_back(e);
  }
  rep.track_epochs = res.track.epochs.size();
  if (res.track.epochs.empty()) {
    const EpochFilterCounts& c = rep.filter;
    throw_input_error(in.pos_files.empty() ? "" : in.pos_files.front().path, 0, "",
                      "no epoch is left for the lamp track: " + std::to_string(c.read) + " read, " +
                          std::to_string(c.dropped_quality) + " dropped for Q, " +
                          std::to_string(c.dropped_sd) + " for sd, " +
                          std::to_string(rep.dropped_no_attitude) +
                          " outside the attitude coverage (check gnss.accept_quality and gnss.max_sd_m)");
  }
  rep.track_start = res.track.epochs.front().utc;
  rep.track_end = res.track.epochs.back().utc;
  std::vector<UtcTime> times;
  times.reserve(res.track.epochs.size());
  for (const LampEpoch& e : res.track.epochs) times.push_back(e.utc);
  rep.gaps = find_gaps(times, in.filter.max_gap_s);

  if (in.lever.source == "total_station" && in.lever.sessions == 1)
    rep.warnings.push_back(
        "the total-station lever arm has a single session: its sd is unknown (taken as 0)");
  if (rep.dropped_no_attitude > 0)
    rep.warnings.push_back(std::to_string(rep.dropped_no_attitude) +
                           " GNSS epochs lie outside the attitude coverage and were dropped");
  if (rep.vertical_form_max_error_m > kVerticalFormWarnM) {
    rep.warnings.push_back("vertical lever-arm form is wrong by up to " + mm(rep.vertical_form_max_error_m) +
                           " (tilt up to " + format_number("%.1f", max_tilt_deg) + " deg; " +
                           std::to_string(rep.vertical_form_epochs_over_5mm) +
                           " epochs over 5 mm): configure lever_arm.body_frd_m to use the attitude");
  }
  return res;
}

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

nlohmann::json gnss_stage_counts(const GnssStageReport& rep, const std::vector<PosFile>& files,
                                 const ResolvedLeverArm& lever) {
  using nlohmann::json;
  json j = json::object();
  json pf = json::array();
  for (const PosFile& f : files)
    pf.push_back({{"path", f.path},
                  {"epochs", f.epochs.size()},
                  {"time_system", to_string(f.header.time_system)},
                  {"time_format", to_string(f.header.time_format)},
                  {"position_format", to_string(f.header.position_format)},
                  {"velocity", f.header.has_velocity}});
  j["pos_files"] = pf;
  j["epochs_read"] = rep.filter.read;
  j["epochs_kept"] = rep.track_epochs;
  j["dropped_quality"] = rep.filter.dropped_quality;
  json byq = json::object();
  for (const auto& [q, n] : rep.filter.dropped_by_quality) byq[std::to_string(q)] = n;
  j["dropped_quality_by_q"] = byq;
  json readq = json::object();
  for (const auto& [q, n] : rep.filter.read_by_quality) readq[std::to_string(q)] = n;
  j["read_by_q"] = readq;
  j["dropped_sd"] = rep.filter.dropped_sd;
  j["dropped_no_attitude"] = rep.dropped_no_attitude;
  j["gaps"] = rep.gaps.size();
  json gl = json::array();
  for (const TimeGap& g : rep.gaps)
    gl.push_back({{"from", format_iso8601_utc(g.from, 9)},
                  {"to", format_iso8601_utc(g.to, 9)},
                  {"duration_s", std::round(g.duration_s() * 1e9) / 1e9}});
  j["gap_list"] = gl;
  j["track_start"] = format_iso8601_utc(rep.track_start, 9);
  j["track_end"] = format_iso8601_utc(rep.track_end, 9);
  j["track_span_s"] = std::round(seconds_between(rep.track_start, rep.track_end) * 1e9) / 1e9;
  json la = {{"source", lever.source}};
  if (lever.form == ResolvedLeverArm::Form::body_frd) {
    la["body_frd_m"] = {lever.body_frd_m[0], lever.body_frd_m[1], lever.body_frd_m[2]};
  } else {
    la["vertical_m"] = lever.vertical_m;
    if (lever.source == "total_station") {
      la["vertical_sd_m"] = lever.vertical_sd_m;
      la["sessions"] = lever.sessions;
    }
    la["vertical_form_max_error_m"] = rep.vertical_form_max_error_m;
    la["vertical_form_epochs_over_5mm"] = rep.vertical_form_epochs_over_5mm;
  }
  j["lever_arm"] = la;
  return j;
}

nlohmann::json attitude_file_counts(const AttitudeFileReport& rep, const std::string& path) {
  using nlohmann::json;
  json j = {{"path", path},
            {"format", to_string(rep.kind)},
            {"samples", rep.samples},
            {"utc_start", format_iso8601_utc(rep.utc_start, 9)},
            {"utc_end", format_iso8601_utc(rep.utc_end, 9)}};
  if (!rep.log) return j;
  const AutopilotAttitudeReport& r = *rep.log;
  const BootTimeFit& f = r.fit;
  j["file_bytes"] = r.file_bytes;
  j["truncated_bytes"] = r.truncated_bytes;
  j["attitude_message"] = r.attitude_message;
  j["attitude_time_field"] = r.attitude_time_field;
  j["attitude_messages"] = r.attitude_messages;
  j["attitude_invalid"] = r.attitude_invalid;
  j["attitude_not_increasing"] = r.attitude_not_increasing;
  j["gps_message"] = r.gps_message;
  j["gps_messages"] = r.gps_messages;
  j["gps_skipped"] = r.gps_skipped;
  j["gps_used"] = f.used;
  j["gps_rejected"] = f.rejected;
  j["gps_span_s"] = static_cast<double>(f.last_boot_us - f.first_boot_us) * 1e-6;
  j["boot_zero_utc"] = format_iso8601_utc(f.to_utc(0), 9);
  j["offset_ns"] = f.offset_ns;
  j["offset_ref_boot_us"] = f.ref_boot_us;
  j["drift_fitted"] = f.drift_fitted;
  j["drift_ppm"] = f.drift_ppm;
  j["residual_rms_us"] = f.residual_rms_us;
  j["residual_max_us"] = f.residual_max_us;
  j["reject_threshold_us"] = f.reject_threshold_us;
  return j;
}

StageLog run_gnss_stage(const MissionConfig& cfg) {
  GnssStageInputs in;
  if (cfg.gnss.pos_files.empty())
    throw_config_error(cfg.config_path, "gnss.pos_files", "at least one .pos file is needed");
  for (const std::string& p : cfg.gnss.pos_files) in.pos_files.push_back(read_rtklib_pos(p));
  AttitudeFileReport attitude_report;
  if (!cfg.attitude_file.empty()) in.attitude = read_attitude_file(cfg.attitude_file, &attitude_report);
  if (cfg.lever_arm.kind == LeverArmConfig::Kind::body_frd && !in.attitude)
    throw_config_error(cfg.config_path, "lever_arm.body_frd_m",
                       "a body-frame lever arm needs attitude.file (or use lever_arm.vertical_m)");
  in.lever = resolve_lever_arm(cfg.lever_arm);
  in.origin = cfg.origin;
  in.filter.accept_quality = cfg.gnss.accept_quality;
  in.filter.max_sd_m = cfg.gnss.max_sd_m;
  in.filter.max_gap_s = cfg.gnss.max_gap_s;
  const GnssStageResult res = compute_lamp_track(in);
  write_lamp_track_csv(lamp_track_path(cfg), res.track);

  StageLog log;
  log.stage = "gnss";
  log.counts = gnss_stage_counts(res.report, in.pos_files, in.lever);
  if (in.attitude) log.counts["attitude"] = attitude_file_counts(attitude_report, cfg.attitude_file);
  log.warnings = res.report.warnings;
  return log;
}

}  // namespace rangecal
