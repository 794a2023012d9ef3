#include "vision/detection/detections_csv.hpp"

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/time/csv_utc.hpp"

namespace rangecal {

bool is_known_lamp_status(const std::string& s) {
  using namespace lamp_status;
  for (const char* k : {kOk, kOkSaturated, kOkByMotion, kNoLamp, kAmbiguous, kStatic, kHotPixel, kLowSnr,
                        kEdge, kExtended, kMissingFrame})
    if (s == k) return true;
  return false;
}

std::string format_detections_csv(const std::vector<LampDetection>& rows) {
  std::string out = "frame,utc,u,v,peak,area,snr,status\n";
  for (const LampDetection& d : rows) {
    out += std::to_string(d.frame);
    out += ',';
    out += format_iso8601_utc(d.utc, 9);
    if (std::isfinite(d.u) && std::isfinite(d.v)) {
      fmt::format_to(std::back_inserter(out), ",{:.4f},{:.4f},{:.1f},{},{:.2f},", d.u, d.v,
                     std::isfinite(d.peak) ? d.peak : 0.0, d.area, std::isfinite(d.snr) ? d.snr : 0.0);
    } else {
      out += ",,,,,,";
    }
    out += d.status;
    out += '\n';
  }
  return out;
}

void write_detections_csv(const std::string& path, const std::vector<LampDetection>& rows) {
  write_file_atomic(path, format_detections_csv(rows));
}

std::vector<LampDetection> read_detections_csv(const std::string& path) {
  return parse_detections_csv(read_file_text(path), path);
}

std::vector<LampDetection> parse_detections_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t c_frame = t.column("frame"), c_utc = t.column("utc"), c_u = t.column("u"),
                    c_v = t.column("v"), c_peak = t.column("peak"), c_area = t.column("area"),
                    c_snr = t.column("snr"), c_status = t.column("status");
  std::vector<LampDetection> out;
  out.reserve(t.records.size());
  for (const CsvRecord& r : t.records) {
    LampDetection d;
    d.frame = t.integer(r, c_frame);
    d.utc = csv_utc(t, r, c_utc);
    if (!t.text(r, c_u).empty() || !t.text(r, c_v).empty()) {
      d.u = t.number(r, c_u);
      d.v = t.number(r, c_v);
      d.peak = t.number(r, c_peak);
      d.area = static_cast<int>(t.integer(r, c_area));
      d.snr = t.number(r, c_snr);
    }
    d.status = t.text(r, c_status);
    if (!is_known_lamp_status(d.status))
      throw_input_error(path, r.line, "status", "unknown status '" + d.status + "'");
    if (d.usable() && !std::isfinite(d.u))
      throw_input_error(path, r.line, "u", "status '" + d.status + "' needs a position");
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace rangecal
