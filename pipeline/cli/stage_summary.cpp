#include "pipeline/cli/stage_summary.hpp"

#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "config/number_format.hpp"
#include "pipeline/io/align_record.hpp"
#include "pipeline/io/calibrate_record.hpp"
#include "pipeline/io/detect_record.hpp"
#include "pipeline/io/gnss_record.hpp"
#include "pipeline/io/intersect_record.hpp"
#include "pipeline/report/flight_volume_sigma.hpp"

namespace rangecal {
namespace {

using nlohmann::json;

// 1,878 — counts read at a glance.
std::string count(long long n) {
  std::string s = std::to_string(n);
  const std::size_t first = (s[0] == '-') ? 1 : 0;
  for (int i = static_cast<int>(s.size()) - 3; i > static_cast<int>(first); i -= 3)
    s.insert(static_cast<std::size_t>(i), ",");
  return s;
}

// A figure that was not computed is "-" or says so, never "nan" (docs/reliability.md "Run outcome").
bool finite_number(const json& v) {
  return v.is_number() && std::isfinite(v.get<double>());
}

std::string fixed(double v, const char* fmt) {
  return std::isfinite(v) ? format_number(fmt, v) : std::string("-");
}

std::string fixed(const json& v, const char* fmt) {
  return finite_number(v) ? fixed(v.get<double>(), fmt) : std::string("-");
}

std::string millimetres(double metres) {
  return std::isfinite(metres) ? format_number("%.1f", metres * 1e3) + " mm" : std::string("not computed");
}

std::string millimetres(const json& metres) {
  return finite_number(metres) ? millimetres(metres.get<double>()) : std::string("not computed");
}

std::string seconds(double s) {
  return s < 10 ? format_number("%.2f", s) + " s" : format_number("%.0f", s) + " s";
}

// "Q1 282, Q2 10" from {1: 282, 2: 10}.
std::string by_quality(const std::map<int, std::size_t>& m) {
  std::string s;
  for (const auto& [q, n] : m) s += (s.empty() ? "" : ", ") + ("Q" + std::to_string(q) + " " + count(n));
  return s;
}

std::string gnss_lines(const GnssRecord& c) {
  std::string s = "  " + count(c.epochs_read) + " epochs read (" + by_quality(c.read_by_q) + "), " +
                  count(c.epochs_kept) + " kept";
  std::string dropped;
  if (c.dropped_quality > 0)
    dropped += count(c.dropped_quality) + " for Q (" + by_quality(c.dropped_quality_by_q) + ")";
  if (c.dropped_sd > 0) dropped += (dropped.empty() ? "" : ", ") + count(c.dropped_sd) + " for sd";
  if (c.dropped_no_attitude > 0)
    dropped += (dropped.empty() ? "" : ", ") + count(c.dropped_no_attitude) + " without attitude";
  if (!dropped.empty()) s += "; dropped " + dropped;
  s += "\n";
  if (!c.track_start.empty())
    s += "  track " + c.track_start + " .. " + c.track_end + " (" + fixed(c.track_span_s, "%.1f") + " s), " +
         count(static_cast<long long>(c.gap_list.size())) + " gap(s)\n";
  return s;
}

std::string align_line(const std::string& cam, const AlignCameraRecord& record) {
  const AlignReport& c = record.report;
  std::string s = "  " + cam + ": " + count(c.frames_aligned) + " of " + count(c.frames) +
                  " frames aligned to " + count(c.epochs) + " epochs";
  std::string rejected;
  for (const auto& [what, n] : {std::pair<const char*, std::size_t>{"offset", c.rejected_offset},
                                {"gap", c.rejected_gap},
                                {"outside_track", c.rejected_outside_track}})
    if (n > 0) rejected += (rejected.empty() ? "" : ", ") + std::string(what) + " " + count(n);
  if (!rejected.empty()) s += " (rejected: " + rejected + ")";
  s += "; max |dt| " + format_number("%.2f", c.max_abs_dt_s * 1e3) + " ms, worst position error " +
       millimetres(c.worst_position_error_m);
  return s + "\n";
}

std::string detect_line(const std::string& cam, const DetectCameraRecord& c) {
  std::string s =
      "  " + cam + ": lamp in " + count(c.correspondences) + " of " + count(c.frames_examined) + " frames";
  std::string rejected;
  for (const auto& [status, n] : c.by_status)
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

std::string intersect_lines(const IntersectRecord& c) {
  std::string s = "  " + count(c.poles_triangulated) + " poles triangulated";
  if (!c.skipped.empty()) return s + "\n";
  s += " with " + std::to_string(c.cameras_used.size()) + " camera(s)\n";
  const IntersectMeansRecord& k = c.check;
  // No check pole, no figure: the line says so rather than printing an undefined mean.
  if (!std::isfinite(k.mean_dR_m))
    return s +
           "  no check pole triangulated: no mean dR (a check pole must be picked in two calibrated "
           "cameras)\n";
  s += "  " + count(k.n) + " check poles: mean dR " + millimetres(k.mean_dR_m) + ", max " +
       millimetres(k.max_dR_m) +
       (std::isfinite(k.mean_sigma_m) ? " (predicted sigma " + millimetres(k.mean_sigma_m) + ")"
                                      : " (no predicted sigma)") +
       "\n";
  return s;
}

template <typename Camera>
std::string per_camera(const std::map<std::string, Camera>& cameras,
                       std::string (*line)(const std::string&, const Camera&)) {
  std::string s;
  for (const auto& [id, c] : cameras) s += line(id, c);
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
  if (log.stage == "gnss") {
    s += gnss_lines(parse_gnss_record(c, "run.json", "stages.gnss.counts"));
  } else if (log.stage == "align") {
    s += per_camera(parse_align_record(c, "run.json", "stages.align.counts").cameras, align_line);
  } else if (log.stage == "detect") {
    s += per_camera(parse_detect_record(c, "run.json", "stages.detect.counts").cameras, detect_line);
  } else if (log.stage == "calibrate") {
    s += calibrate_lines(parse_calibrate_record(c, "run.json", "stages.calibrate.counts"));
  } else if (log.stage == "intersect") {
    s += intersect_lines(parse_intersect_record(c, "run.json", "stages.intersect.counts"));
  } else if (log.stage == "report") {
    s += flight_volume_line(c);
  }
  if (verbose)
    for (const auto& [key, value] : c.items()) s += "  " + key + ": " + value.dump() + "\n";
  for (const std::string& w : log.warnings) s += "  warning: " + w + "\n";
  return s;
}

}  // namespace rangecal
