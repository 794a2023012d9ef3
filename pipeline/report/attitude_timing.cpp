#include "pipeline/report/attitude_timing.hpp"

#include "config/number_format.hpp"

namespace rangecal {
namespace {

std::optional<double> number_at(const nlohmann::json& j, const char* key) {
  if (!j.is_object() || !j.contains(key) || !j[key].is_number()) return std::nullopt;
  return j[key].get<double>();
}

}  // namespace

std::optional<AttitudeTiming> attitude_timing(const nlohmann::json& stages) {
  if (!stages.is_object() || !stages.contains("gnss") || !stages["gnss"].is_object()) return std::nullopt;
  const nlohmann::json& gnss = stages["gnss"];
  if (!gnss.contains("counts") || !gnss["counts"].is_object()) return std::nullopt;
  const nlohmann::json& counts = gnss["counts"];
  if (!counts.contains("attitude") || !counts["attitude"].is_object()) return std::nullopt;
  const nlohmann::json& a = counts["attitude"];
  const std::optional<double> lag = number_at(a, "gnss_lag_ms");
  if (!lag) return std::nullopt;
  AttitudeTiming t;
  t.gnss_lag_ms = *lag;
  t.format = a.contains("format") && a["format"].is_string() ? a["format"].get<std::string>() : "";
  t.lag_source = a.contains("gnss_lag_source") && a["gnss_lag_source"].is_string()
                     ? a["gnss_lag_source"].get<std::string>()
                     : "";
  if (counts.contains("lever_arm")) {
    t.motion_max_mm_per_ms = number_at(counts["lever_arm"], "motion_max_mm_per_ms");
    t.motion_rms_mm_per_ms = number_at(counts["lever_arm"], "motion_rms_mm_per_ms");
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
