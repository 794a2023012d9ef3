#pragma once
// The gnss stage's record: run.json `stages.gnss.counts` (docs/outputs.md, docs/gnss.md). One writer
// and one reader, so the stage, the report and the console summaries share the keys:
//   pos_files [{path, epochs, time_system, time_format, position_format, velocity}]
//   epochs_read, epochs_kept, dropped_quality, dropped_quality_by_q {Q: n}, read_by_q {Q: n},
//   dropped_sd, dropped_no_attitude, gaps, gap_list [{from, to, duration_s}],
//   track_start, track_end, track_span_s,
//   lever_arm {source, body_frd_m, motion_max/rms_mm_per_ms} (body_frd) or {source, vertical_m,
//             vertical_sd_m and sessions (total_station), vertical_form_max_error_m,
//             vertical_form_epochs_over_5mm}
//   attitude  {path, format, samples, utc_start, utc_end, and for an autopilot log its message
//             counts, the boot-time -> UTC fit and the GNSS receiver lag}, when the mission has one
// Times are ISO 8601 UTC text as the stage formats them (ns); `gaps` is gap_list's length.
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace rangecal {

/// One .pos file as read (gnss/formats/rtklib_pos_reader.hpp).
struct PosFileRecord {
  std::string path;
  std::size_t epochs = 0;
  std::string time_system, time_format, position_format;
  bool velocity = false;
};

/// A gap of the kept epochs longer than gnss.max_gap_s.
struct GapRecord {
  std::string from, to;  ///< ISO 8601 UTC
  double duration_s = 0;
};

/// The lever arm as resolved, and what it does to the track (docs/gnss.md "Lever arm").
struct LeverArmRecord {
  std::string source;  ///< body_frd | vertical | total_station
  // body_frd: the arm in the body frame and the lamp motion per ms of attitude timing error.
  std::array<double, 3> body_frd_m{};
  double motion_max_mm_per_ms = 0, motion_rms_mm_per_ms = 0;
  // vertical and total_station: the lamp this far below the antenna; the total station's 1σ.
  double vertical_m = 0, vertical_sd_m = 0;
  int sessions = 0;
  double vertical_form_max_error_m = 0;
  std::size_t vertical_form_epochs_over_5mm = 0;
};

/// An autopilot log's reading and its boot-time -> UTC fit (gnss/formats/autopilot_attitude_report.hpp,
/// gnss/time/boot_time_fit.hpp).
struct AutopilotLogRecord {
  std::size_t file_bytes = 0, truncated_bytes = 0;
  std::string attitude_message, attitude_time_field;
  std::size_t attitude_messages = 0, attitude_invalid = 0, attitude_not_increasing = 0;
  std::string gps_message;
  std::size_t gps_messages = 0, gps_skipped = 0, gps_used = 0, gps_rejected = 0;
  double gps_span_s = 0;
  std::string boot_zero_utc;
  std::int64_t offset_ns = 0, offset_ref_boot_us = 0;
  bool drift_fitted = false;
  double drift_ppm = 0, residual_rms_us = 0, residual_max_us = 0, reject_threshold_us = 0;
  double gnss_lag_ms = 0;
  std::string gnss_lag_source;  ///< "attitude.gnss_lag_ms" or "default for <format>"
};

/// The attitude file (gnss/formats/attitude_file.hpp).
struct AttitudeRecord {
  std::string path, format;
  std::size_t samples = 0;
  std::string utc_start, utc_end;
  std::optional<AutopilotLogRecord> log;  ///< a PX4 ULog or ArduPilot DataFlash log; read back when
                                          ///< `gnss_lag_ms` is there
};

struct GnssRecord {
  std::vector<PosFileRecord> pos_files;
  std::size_t epochs_read = 0, epochs_kept = 0, dropped_quality = 0;
  std::map<int, std::size_t> dropped_quality_by_q, read_by_q;  ///< by solution quality Q
  std::size_t dropped_sd = 0, dropped_no_attitude = 0;
  std::vector<GapRecord> gap_list;
  std::string track_start, track_end;
  double track_span_s = 0;
  LeverArmRecord lever_arm;
  std::optional<AttitudeRecord> attitude;  ///< absent: the mission has no attitude file
};

/// The record as run.json holds it.
nlohmann::json gnss_record_json(const GnssRecord& r);

/// Parses `j` as gnss_record_json wrote it. `path` and `field` (e.g. "stages.gnss.counts") name it
/// in messages: a value of the wrong type throws rangecal::Error (input) naming `field.<key>`. Keys
/// it does not know are left alone; a missing one keeps its default.
GnssRecord parse_gnss_record(const nlohmann::json& j, const std::string& path, const std::string& field);

}  // namespace rangecal
