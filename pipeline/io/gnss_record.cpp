#include "pipeline/io/gnss_record.hpp"

#include <cstdlib>

#include "config/error.hpp"
#include "config/json_view.hpp"
#include "pipeline/io/record_fields.hpp"

namespace rangecal {
namespace {

using nlohmann::json;

// Each part's scalar keys, in the order they are read. A part whose keys stand around others that
// are not scalars (an array, a map by quality, an object) lists them in several tables, in order.
const RecordField<PosFileRecord> kPosFileFields[] = {
    {"path", &PosFileRecord::path},
    {"epochs", &PosFileRecord::epochs},
    {"time_system", &PosFileRecord::time_system},
    {"time_format", &PosFileRecord::time_format},
    {"position_format", &PosFileRecord::position_format},
    {"velocity", &PosFileRecord::velocity},
};
const RecordField<GapRecord> kGapFields[] = {
    {"from", &GapRecord::from},
    {"to", &GapRecord::to},
    {"duration_s", &GapRecord::duration_s},
};

// The lever arm: body_frd_m stands between the source and the body-frame motion; the vertical
// forms' keys follow.
const RecordField<LeverArmRecord> kLeverSourceFields[] = {
    {"source", &LeverArmRecord::source},
};
const RecordField<LeverArmRecord> kLeverMotionFields[] = {
    {"motion_max_mm_per_ms", &LeverArmRecord::motion_max_mm_per_ms},
    {"motion_rms_mm_per_ms", &LeverArmRecord::motion_rms_mm_per_ms},
};
const RecordField<LeverArmRecord> kLeverVerticalFields[] = {
    {"vertical_m", &LeverArmRecord::vertical_m},
};
const RecordField<LeverArmRecord> kLeverTotalStationFields[] = {
    {"vertical_sd_m", &LeverArmRecord::vertical_sd_m},
    {"sessions", &LeverArmRecord::sessions},
};
const RecordField<LeverArmRecord> kLeverVerticalFormFields[] = {
    {"vertical_form_max_error_m", &LeverArmRecord::vertical_form_max_error_m},
    {"vertical_form_epochs_over_5mm", &LeverArmRecord::vertical_form_epochs_over_5mm},
};

const RecordField<AutopilotLogRecord> kLogFields[] = {
    {"file_bytes", &AutopilotLogRecord::file_bytes},
    {"truncated_bytes", &AutopilotLogRecord::truncated_bytes},
    {"attitude_message", &AutopilotLogRecord::attitude_message},
    {"attitude_time_field", &AutopilotLogRecord::attitude_time_field},
    {"attitude_messages", &AutopilotLogRecord::attitude_messages},
    {"attitude_invalid", &AutopilotLogRecord::attitude_invalid},
    {"attitude_not_increasing", &AutopilotLogRecord::attitude_not_increasing},
    {"gps_message", &AutopilotLogRecord::gps_message},
    {"gps_messages", &AutopilotLogRecord::gps_messages},
    {"gps_skipped", &AutopilotLogRecord::gps_skipped},
    {"gps_used", &AutopilotLogRecord::gps_used},
    {"gps_rejected", &AutopilotLogRecord::gps_rejected},
    {"gps_span_s", &AutopilotLogRecord::gps_span_s},
    {"boot_zero_utc", &AutopilotLogRecord::boot_zero_utc},
    {"offset_ns", &AutopilotLogRecord::offset_ns},
    {"offset_ref_boot_us", &AutopilotLogRecord::offset_ref_boot_us},
    {"drift_fitted", &AutopilotLogRecord::drift_fitted},
    {"drift_ppm", &AutopilotLogRecord::drift_ppm},
    {"residual_rms_us", &AutopilotLogRecord::residual_rms_us},
    {"residual_max_us", &AutopilotLogRecord::residual_max_us},
    {"reject_threshold_us", &AutopilotLogRecord::reject_threshold_us},
    {"gnss_lag_ms", &AutopilotLogRecord::gnss_lag_ms},
    {"gnss_lag_source", &AutopilotLogRecord::gnss_lag_source},
};
// The attitude file; an autopilot log's keys follow in the same object.
const RecordField<AttitudeRecord> kAttitudeFields[] = {
    {"path", &AttitudeRecord::path},       {"format", &AttitudeRecord::format},
    {"samples", &AttitudeRecord::samples}, {"utc_start", &AttitudeRecord::utc_start},
    {"utc_end", &AttitudeRecord::utc_end},
};

// The record itself: pos_files, the maps by quality, gap_list, lever_arm and attitude stand around
// these parts.
const RecordField<GnssRecord> kEpochFields[] = {
    {"epochs_read", &GnssRecord::epochs_read},
    {"epochs_kept", &GnssRecord::epochs_kept},
    {"dropped_quality", &GnssRecord::dropped_quality},
};
const RecordField<GnssRecord> kDroppedFields[] = {
    {"dropped_sd", &GnssRecord::dropped_sd},
    {"dropped_no_attitude", &GnssRecord::dropped_no_attitude},
};
const RecordField<GnssRecord> kTrackFields[] = {
    {"track_start", &GnssRecord::track_start},
    {"track_end", &GnssRecord::track_end},
    {"track_span_s", &GnssRecord::track_span_s},
};

json by_quality_json(const std::map<int, std::size_t>& m) {
  json j = json::object();
  for (const auto& [q, n] : m) j[std::to_string(q)] = n;
  return j;
}

json lever_arm_json(const LeverArmRecord& l) {
  json j;
  write_fields(kLeverSourceFields, l, &j);
  if (l.source == "body_frd") {
    j["body_frd_m"] = {l.body_frd_m[0], l.body_frd_m[1], l.body_frd_m[2]};
    write_fields(kLeverMotionFields, l, &j);
    return j;
  }
  write_fields(kLeverVerticalFields, l, &j);
  if (l.source == "total_station") write_fields(kLeverTotalStationFields, l, &j);
  write_fields(kLeverVerticalFormFields, l, &j);
  return j;
}

json attitude_json(const AttitudeRecord& r) {
  json j;
  write_fields(kAttitudeFields, r, &j);
  if (r.log) write_fields(kLogFields, *r.log, &j);
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
  read_fields(kPosFileFields, v, &f);
  return f;
}

GapRecord parse_gap(const JsonView& v) {
  v.require_object("an object {from, to, duration_s}");
  GapRecord g;
  read_fields(kGapFields, v, &g);
  return g;
}

LeverArmRecord parse_lever_arm_record(const JsonView& v) {
  LeverArmRecord l;
  read_fields(kLeverSourceFields, v, &l);
  if (const auto b = v.find("body_frd_m")) {
    const std::vector<double> m = b->numbers(3, "an array of 3 numbers (m)");
    l.body_frd_m = {m[0], m[1], m[2]};
  }
  read_fields(kLeverMotionFields, v, &l);
  read_fields(kLeverVerticalFields, v, &l);
  read_fields(kLeverTotalStationFields, v, &l);
  read_fields(kLeverVerticalFormFields, v, &l);
  return l;
}

AttitudeRecord parse_attitude_record(const JsonView& v) {
  AttitudeRecord r;
  read_fields(kAttitudeFields, v, &r);
  if (v.has("gnss_lag_ms")) read_fields(kLogFields, v, &r.log.emplace());
  return r;
}

}  // namespace

nlohmann::json gnss_record_json(const GnssRecord& r) {
  json j = json::object();
  json pf = json::array();
  for (const PosFileRecord& f : r.pos_files) write_fields(kPosFileFields, f, &pf.emplace_back());
  j["pos_files"] = pf;
  write_fields(kEpochFields, r, &j);
  j["dropped_quality_by_q"] = by_quality_json(r.dropped_quality_by_q);
  j["read_by_q"] = by_quality_json(r.read_by_q);
  write_fields(kDroppedFields, r, &j);
  j["gaps"] = r.gap_list.size();
  json gl = json::array();
  for (const GapRecord& g : r.gap_list) write_fields(kGapFields, g, &gl.emplace_back());
  j["gap_list"] = gl;
  write_fields(kTrackFields, r, &j);
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
  read_fields(kEpochFields, v, &r);
  r.dropped_quality_by_q = parse_by_quality(v, "dropped_quality_by_q");
  r.read_by_q = parse_by_quality(v, "read_by_q");
  read_fields(kDroppedFields, v, &r);
  if (const auto gl = v.find("gap_list")) {
    const std::size_t n = gl->require_array("an array of {from, to, duration_s}");
    for (std::size_t i = 0; i < n; ++i) r.gap_list.push_back(parse_gap(gl->element(i)));
  }
  read_fields(kTrackFields, v, &r);
  if (const auto l = object_field(v, "lever_arm", "an object {source, ...}"))
    r.lever_arm = parse_lever_arm_record(*l);
  if (const auto a = object_field(v, "attitude", "an object {path, format, samples, ...}"))
    r.attitude = parse_attitude_record(*a);
  return r;
}

}  // namespace rangecal
