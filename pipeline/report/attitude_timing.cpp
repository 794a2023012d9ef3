#include "pipeline/report/attitude_timing.hpp"

#include "config/number_format.hpp"
#include "pipeline/io/gnss_record.hpp"

namespace rangecal {

std::optional<AttitudeTiming> attitude_timing(const nlohmann::json& stages) {
  if (!stages.is_object() || !stages.contains("gnss") || !stages["gnss"].is_object()) return std::nullopt;
  const nlohmann::json& gnss = stages["gnss"];
  if (!gnss.contains("counts") || !gnss["counts"].is_object()) return std::nullopt;
  const GnssRecord record = parse_gnss_record(gnss["counts"], "run.json", "stages.gnss.counts");
  if (!record.attitude || !record.attitude->log) return std::nullopt;
  AttitudeTiming t;
  t.gnss_lag_ms = record.attitude->log->gnss_lag_ms;
  t.format = record.attitude->format;
  t.lag_source = record.attitude->log->gnss_lag_source;
  if (record.lever_arm.source == "body_frd") {
    t.motion_max_mm_per_ms = record.lever_arm.motion_max_mm_per_ms;
    t.motion_rms_mm_per_ms = record.lever_arm.motion_rms_mm_per_ms;
  }
  return t;
}

std::string attitude_timing_sentence(const AttitudeTiming& t) {
  std::string s = "Attitude: " + (t.format.empty() ? std::string("autopilot") : t.format) +
                  " log put on UTC with a GNSS receiver lag of " + format_number("%g", t.gnss_lag_ms) + " ms";
  if (!t.lag_source.empty()) s += " (" + t.lag_source + ")";
  s += ".";
  if (t.motion_max_mm_per_ms && t.motion_rms_mm_per_ms)
    s += " Through the lever arm a timing error moves the lamp by up to " +
         format_number("%.3f", *t.motion_max_mm_per_ms) + " mm per ms (rms " +
         format_number("%.3f", *t.motion_rms_mm_per_ms) + "): 10 ms of lag error, up to " +
         format_number("%.1f", 10 * *t.motion_max_mm_per_ms) + " mm.";
  return s;
}

}  // namespace rangecal
