#include "pipeline/cli/stage_summary.hpp"

#include <cmath>
#include <string>

#include "config/number_format.hpp"
#include "pipeline/io/calibrate_record.hpp"
#include "pipeline/report/flight_volume_sigma.hpp"

namespace rangecal {
namespace {

using nlohmann::json;

// 1,878 — counts read at a glance.
std::string count(const json& v) {
  if (!v.is_number()) return "0";
  std::string s = std::to_string(v.get<long long>());
  const std::size_t first = (s[0] == '-') ? 1 : 0;
  for (int i = static_cast<int>(s.size()) - 3; i > static_cast<int>(first); i -= 3)
    s.insert(static_cast<std::size_t>(i), ",");
  return s;
}

// A figure that was not computed is "-" or says so, never "nan" (docs/reliability.md "Run outcome").
bool finite_number(const json& v) {
  return v.is_number() && std::isfinite(v.get<double>());
}

std::string fixed(const json& v, const char* fmt) {
  return finite_number(v) ? format_number(fmt, v.get<double>()) : std::string("-");
}

std::string millimetres(const json& metres) {
  return finite_number(metres) ? format_number("%.1f", metres.get<double>() * 1e3) + " mm"
                               : std::string("not computed");
}

std::string seconds(double s) {
  return s < 10 ? format_number("%.2f", s) + " s" : format_number("%.0f", s) + " s";
}

// "Q1 282, Q2 10" from {"1": 282, "2": 10}.
std::string by_quality(const json& m) {
  std::string s;
  if (!m.is_object()) return s;
  for (const auto& [q, n] : m.items()) s += (s.empty() ? "" : ", ") + ("Q" + q + " " + count(n));
  return s;
}

std::string gnss_lines(const json& c) {
  std::string s = "  " + count(c.value("epochs_read", json())) + " epochs read (" +
                  by_quality(c.value("read_by_q", json())) + "), " + count(c.value("epochs_kept", json())) +
                  " kept";
  std::string dropped;
  if (c.value("dropped_quality", 0) > 0)
    dropped +=
        count(c["dropped_quality"]) + " for Q (" + by_quality(c.value("dropped_quality_by_q", json())) + ")";
  if (c.value("dropped_sd", 0) > 0)
    dropped += (dropped.empty() ? "" : ", ") + count(c["dropped_sd"]) + " for sd";
  if (c.value("dropped_no_attitude", 0) > 0)
    dropped += (dropped.empty() ? "" : ", ") + count(c["dropped_no_attitude"]) + " without attitude";
  if (!dropped.empty()) s += "; dropped " + dropped;
  s += "\n";
  if (c.contains("track_start"))
    s += "  track " + c["track_start"].get<std::string>() + " .. " + c["track_end"].get<std::string>() +
         " (" + fixed(c.value("track_span_s", json()), "%.1f") + " s), " + count(c.value("gaps", json())) +
         " gap(s)\n";
  return s;
}

std::string align_line(const std::string& cam, const json& c) {
  std::string s = "  " + cam + ": " + count(c.value("frames_aligned", json())) + " of " +
                  count(c.value("frames", json())) + " frames aligned to " +
                  count(c.value("epochs", json())) + " epochs";
  std::string rejected;
  for (const char* key : {"rejected_offset", "rejected_gap", "rejected_outside_track"})
    if (c.value(key, 0) > 0)
      rejected += (rejected.empty() ? "" : ", ") + std::string(key + 9) + " " + count(c[key]);
  if (!rejected.empty()) s += " (rejected: " + rejected + ")";
  if (c.contains("max_abs_dt_s"))
    s += "; max |dt| " + format_number("%.2f", c.value("max_abs_dt_s", 0.0) * 1e3) +
         " ms, worst position error " + millimetres(c.value("worst_position_error_m", json()));
  return s + "\n";
}

std::string detect_line(const std::string& cam, const json& c) {
  std::string s = "  " + cam + ": lamp in " + count(c.value("correspondences", json())) + " of " +
                  count(c.value("frames_examined", json())) + " frames";
  std::string rejected;
  if (c.contains("by_status"))
    for (const auto& [status, n] : c["by_status"].items())
      if (status != "ok") rejected += (rejected.empty() ? "" : ", ") + status + " " + count(n);
  if (!rejected.empty()) s += " (" + rejected + ")";
  return s + "\n";
}

std::string calibrate_lines(const CalibrateRecord& r) {
  std::string s;
  for (const auto& [cam, c] : r.cameras)
    s += c.failed.empty() ? "  " + cam + ": " + c.method + ", " + count(c.n_used) + " points used, " +
                                count(c.n_rejected) + " rejected, rms " + fixed(c.rms_px, "%.2f") + " px\n"
                          : "  " + cam + ": FAILED\n";
  if (r.method_choice) s += "  method: " + r.method_choice->method + " (" + r.method_choice->why + ")\n";
  return s;
}

std::string intersect_lines(const json& c) {
  std::string s = "  " + count(c.value("poles_triangulated", json())) + " poles triangulated";
  if (c.contains("cameras_used") && c["cameras_used"].is_array())
    s += " with " + std::to_string(c["cameras_used"].size()) + " camera(s)";
  s += "\n";
  if (c.contains("check") && c["check"].is_object()) {
    const json& k = c["check"];
    // No check pole, no figure: the line says so rather than printing an undefined mean.
    if (!finite_number(k.value("mean_dR_m", json())))
      return s +
             "  no check pole triangulated: no mean dR (a check pole must be picked in two calibrated "
             "cameras)\n";
    const json sigma = k.value("mean_sigma_m", json());
    s += "  " + count(k.value("n", json())) + " check poles: mean dR " +
         millimetres(k.value("mean_dR_m", json())) + ", max " + millimetres(k.value("max_dR_m", json())) +
         (finite_number(sigma) ? " (predicted sigma " + millimetres(sigma) + ")" : " (no predicted sigma)") +
         "\n";
  }
  return s;
}

std::string per_camera(const json& counts, std::string (*line)(const std::string&, const json&)) {
  std::string s;
  for (const auto& [key, value] : counts.items())
    if (value.is_object()) s += line(key, value);
  return s;
}

}  // namespace

std::string flight_volume_line(const json& c) {
  if (!c.contains("prediction") || !c["prediction"].is_object()) return "";
  const json& p = c["prediction"];
  if (!finite_number(p.value("median_sigma_m", json()))) return "";
  std::string s = "  flight volume: intersection sigma " + millimetres(p["median_sigma_m"]) +
                  " median (max " + millimetres(p.value("max_sigma_m", json())) + ")";
  const json ratio = p.value("over_datum_floor", json());
  if (finite_number(ratio))
    s += "; datum floor " + millimetres(p.value("datum_floor_median_sigma_m", json())) + " (" +
         fixed(ratio, "%.2f") + "x): " +
         (ratio.get<double>() <= kDatumLimitedRatio ? "the PPK fixes and control limit it, not the images"
                                                    : "the images still limit it");
  return s + "\n";
}

std::string stage_summary(const StageLog& log, bool verbose) {
  std::string s = log.stage + " (" + seconds(log.wall_time_s) + ")\n";
  const json& c = log.counts;
  if (log.stage == "gnss")
    s += gnss_lines(c);
  else if (log.stage == "align")
    s += per_camera(c, align_line);
  else if (log.stage == "detect")
    s += per_camera(c, detect_line);
  else if (log.stage == "calibrate") {
    s += calibrate_lines(parse_calibrate_record(c, "run.json", "stages.calibrate.counts"));
  } else if (log.stage == "intersect") {
    s += intersect_lines(c);
  } else if (log.stage == "report") {
    s += flight_volume_line(c);
  }
  if (verbose)
    for (const auto& [key, value] : c.items()) s += "  " + key + ": " + value.dump() + "\n";
  for (const std::string& w : log.warnings) s += "  warning: " + w + "\n";
  return s;
}

}  // namespace rangecal
