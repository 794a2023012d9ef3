#include "pipeline/io/gnss_record.hpp"

#include <cstdlib>

#include "config/error.hpp"
#include "config/json_view.hpp"
#include "pipeline/io/record_fields.hpp"

namespace rangecal {
namespace {

using nlohmann::json;

json by_quality_json(const std::map<int, std::size_t>& m) {
  json j = json::object();
  for (const auto& [q, n] : m) j[std::to_string(q)] = n;
  return j;
}

json lever_arm_json(const LeverArmRecord& l) {
  json j = {{"source", l.source}};
  if (l.source == "body_frd") {
    j["body_frd_m"] = {l.body_frd_m[0], l.body_frd_m[1], l.body_frd_m[2]};
    j["motion_max_mm_per_ms"] = l.motion_max_mm_per_ms;
    j["motion_rms_mm_per_ms"] = l.motion_rms_mm_per_ms;
    return j;
  }
  j["vertical_m"] = l.vertical_m;
  if (l.source == "total_station") {
    j["vertical_sd_m"] = l.vertical_sd_m;
    j["sessions"] = l.sessions;
  }
  j["vertical_form_max_error_m"] = l.vertical_form_max_error_m;
  j["vertical_form_epochs_over_5mm"] = l.vertical_form_epochs_over_5mm;
  return j;
}

void add_log_json(const AutopilotLogRecord& r, json* j) {
  json& a = *j;
  a["file_bytes"] = r.file_bytes;
  a["truncated_bytes"] = r.truncated_bytes;
  a["attitude_message"] = r.attitude_message;
  a["attitude_time_field"] = r.attitude_time_field;
  a["attitude_messages"] = r.attitude_messages;
  a["attitude_invalid"] = r.attitude_invalid;
  a["attitude_not_increasing"] = r.attitude_not_increasing;
  a["gps_message"] = r.gps_message;
  a["gps_messages"] = r.gps_messages;
  a["gps_skipped"] = r.gps_skipped;
  a["gps_used"] = r.gps_used;
  a["gps_rejected"] = r.gps_rejected;
  a["gps_span_s"] = r.gps_span_s;
  a["boot_zero_utc"] = r.boot_zero_utc;
  a["offset_ns"] = r.offset_ns;
  a["offset_ref_boot_us"] = r.offset_ref_boot_us;
  a["drift_fitted"] = r.drift_fitted;
  a["drift_ppm"] = r.drift_ppm;
  a["residual_rms_us"] = r.residual_rms_us;
  a["residual_max_us"] = r.residual_max_us;
  a["reject_threshold_us"] = r.reject_threshold_us;
  a["gnss_lag_ms"] = r.gnss_lag_ms;
  a["gnss_lag_source"] = r.gnss_lag_source;
}

json attitude_json(const AttitudeRecord& r) {
  json j = {{"path", r.path},
            {"format", r.format},
            {"samples", r.samples},
            {"utc_start", r.utc_start},
            {"utc_end", r.utc_end}};
  if (r.log) add_log_json(*r.log, &j);
  return j;
}

// {"1": 282, "2": 10}: the keys are solution qualities Q.
std::map<int, std::size_t> parse_by_quality(const JsonView& v, const std::string& key) {
  std::map<int, std::size_t> out;
  for (const auto& [q, n] : counts_field(v, key)) {
    char* end = nullptr;
    const long k = std::strtol(q.c_str(), &end, 10);
    if (q.empty() || *end != '\0' || k < 0 || k > 999)
      JsonView(v.json().at(key).at(q), v.file(), v.path() + "." + key + "." + q, ErrorKind::input)
          .fail("the key is not a solution quality Q (a small non-negative integer)");
    out[static_cast<int>(k)] = n;
  }
  return out;
}

PosFileRecord parse_pos_file(const JsonView& v) {
  v.require_object("an object {path, epochs, time_system, time_format, position_format, velocity}");
  PosFileRecord f;
  f.path = string_field(v, "path");
  f.epochs = count_field(v, "epochs");
  f.time_system = string_field(v, "time_system");
  f.time_format = string_field(v, "time_format");
  f.position_format = string_field(v, "position_format");
  f.velocity = bool_field(v, "velocity");
  return f;
}

GapRecord parse_gap(const JsonView& v) {
  v.require_object("an object {from, to, duration_s}");
  return {string_field(v, "from"), string_field(v, "to"), number_field(v, "duration_s")};
}

LeverArmRecord parse_lever_arm(const JsonView& v) {
  LeverArmRecord l;
  l.source = string_field(v, "source");
  if (const auto b = v.find("body_frd_m")) {
    const std::vector<double> m = b->numbers(3, "an array of 3 numbers (m)");
    l.body_frd_m = {m[0], m[1], m[2]};
  }
  l.motion_max_mm_per_ms = number_field(v, "motion_max_mm_per_ms");
  l.motion_rms_mm_per_ms = number_field(v, "motion_rms_mm_per_ms");
  l.vertical_m = number_field(v, "vertical_m");
  l.vertical_sd_m = number_field(v, "vertical_sd_m");
  l.sessions = static_cast<int>(integer_field(v, "sessions"));
  l.vertical_form_max_error_m = number_field(v, "vertical_form_max_error_m");
  l.vertical_form_epochs_over_5mm = count_field(v, "vertical_form_epochs_over_5mm");
  return l;
}

AutopilotLogRecord parse_log(const JsonView& v) {
  AutopilotLogRecord r;
  r.file_bytes = count_field(v, "file_bytes");
  r.truncated_bytes = count_field(v, "truncated_bytes");
  r.attitude_message = string_field(v, "attitude_message");
  r.attitude_time_field = string_field(v, "attitude_time_field");
  r.attitude_messages = count_field(v, "attitude_messages");
  r.attitude_invalid = count_field(v, "attitude_invalid");
  r.attitude_not_increasing = count_field(v, "attitude_not_increasing");
  r.gps_message = string_field(v, "gps_message");
  r.gps_messages = count_field(v, "gps_messages");
  r.gps_skipped = count_field(v, "gps_skipped");
  r.gps_used = count_field(v, "gps_used");
  r.gps_rejected = count_field(v, "gps_rejected");
  r.gps_span_s = number_field(v, "gps_span_s");
  r.boot_zero_utc = string_field(v, "boot_zero_utc");
  r.offset_ns = integer_field(v, "offset_ns");
  r.offset_ref_boot_us = integer_field(v, "offset_ref_boot_us");
  r.drift_fitted = bool_field(v, "drift_fitted");
  r.drift_ppm = number_field(v, "drift_ppm");
  r.residual_rms_us = number_field(v, "residual_rms_us");
  r.residual_max_us = number_field(v, "residual_max_us");
  r.reject_threshold_us = number_field(v, "reject_threshold_us");
  r.gnss_lag_ms = number_field(v, "gnss_lag_ms");
  r.gnss_lag_source = string_field(v, "gnss_lag_source");
  return r;
}

AttitudeRecord parse_attitude(const JsonView& v) {
  AttitudeRecord r;
  r.path = string_field(v, "path");
  r.format = string_field(v, "format");
  r.samples = count_field(v, "samples");
  r.utc_start = string_field(v, "utc_start");
  r.utc_end = string_field(v, "utc_end");
  if (v.has("gnss_lag_ms")) r.log = parse_log(v);
  return r;
}

}  // namespace

nlohmann::json gnss_record_json(const GnssRecord& r) {
  json j = json::object();
  json pf = json::array();
  for (const PosFileRecord& f : r.pos_files)
    pf.push_back({{"path", f.path},
                  {"epochs", f.epochs},
                  {"time_system", f.time_system},
                  {"time_format", f.time_format},
                  {"position_format", f.position_format},
                  {"velocity", f.velocity}});
  j["pos_files"] = pf;
  j["epochs_read"] = r.epochs_read;
  j["epochs_kept"] = r.epochs_kept;
  j["dropped_quality"] = r.dropped_quality;
  j["dropped_quality_by_q"] = by_quality_json(r.dropped_quality_by_q);
  j["read_by_q"] = by_quality_json(r.read_by_q);
  j["dropped_sd"] = r.dropped_sd;
  j["dropped_no_attitude"] = r.dropped_no_attitude;
  j["gaps"] = r.gap_list.size();
  json gl = json::array();
  for (const GapRecord& g : r.gap_list)
    gl.push_back({{"from", g.from}, {"to", g.to}, {"duration_s", g.duration_s}});
  j["gap_list"] = gl;
  j["track_start"] = r.track_start;
  j["track_end"] = r.track_end;
  j["track_span_s"] = r.track_span_s;
  j["lever_arm"] = lever_arm_json(r.lever_arm);
  if (r.attitude) j["attitude"] = attitude_json(*r.attitude);
  return j;
}

GnssRecord parse_gnss_record(const nlohmann::json& j, const std::string& path, const std::string& field) {
  const JsonView v(j, path, field, ErrorKind::input);
  v.require_object("an object {pos_files, epochs_read, epochs_kept, ...}");
  GnssRecord r;
  if (const auto pf = v.find("pos_files")) {
    const std::size_t n = pf->require_array("an array of {path, epochs, ...}");
    for (std::size_t i = 0; i < n; ++i) r.pos_files.push_back(parse_pos_file(pf->element(i)));
  }
  r.epochs_read = count_field(v, "epochs_read");
  r.epochs_kept = count_field(v, "epochs_kept");
  r.dropped_quality = count_field(v, "dropped_quality");
  r.dropped_quality_by_q = parse_by_quality(v, "dropped_quality_by_q");
  r.read_by_q = parse_by_quality(v, "read_by_q");
  r.dropped_sd = count_field(v, "dropped_sd");
  r.dropped_no_attitude = count_field(v, "dropped_no_attitude");
  if (const auto gl = v.find("gap_list")) {
    const std::size_t n = gl->require_array("an array of {from, to, duration_s}");
    for (std::size_t i = 0; i < n; ++i) r.gap_list.push_back(parse_gap(gl->element(i)));
  }
  r.track_start = string_field(v, "track_start");
  r.track_end = string_field(v, "track_end");
  r.track_span_s = number_field(v, "track_span_s");
  if (const auto l = object_field(v, "lever_arm", "an object {source, ...}"))
    r.lever_arm = parse_lever_arm(*l);
  if (const auto a = object_field(v, "attitude", "an object {path, format, samples, ...}"))
    r.attitude = parse_attitude(*a);
  return r;
}

}  // namespace rangecal
