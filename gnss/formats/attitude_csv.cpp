#include "gnss/formats/attitude_csv.hpp"

#include <cmath>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "gnss/time/csv_utc.hpp"

namespace rangecal {

AttitudeSeries parse_attitude_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t cu = t.column("utc"), cr = t.column("roll_deg"), cp = t.column("pitch_deg"),
                    cy = t.column("yaw_deg");
  AttitudeSeries s;
  s.path = path;
  s.samples.reserve(t.records.size());
  for (const CsvRecord& r : t.records) {
    AttitudeSample a;
    a.line = r.line;
    a.utc = csv_utc(t, r, cu);
    a.att.roll_deg = t.number(r, cr);
    a.att.pitch_deg = t.number(r, cp);
    a.att.yaw_deg = t.number(r, cy);
    if (std::abs(a.att.roll_deg) > 180)
      throw_input_error(path, r.line, "roll_deg",
                        "roll " + t.text(r, cr) + " is outside [-180, 180] degrees");
    if (std::abs(a.att.pitch_deg) > 90)
      throw_input_error(path, r.line, "pitch_deg",
                        "pitch " + t.text(r, cp) + " is outside [-90, 90] degrees");
    if (std::abs(a.att.yaw_deg) > 360)
      throw_input_error(path, r.line, "yaw_deg", "yaw " + t.text(r, cy) + " is outside [-360, 360] degrees");
    if (!s.samples.empty() && a.utc <= s.samples.back().utc)
      throw_input_error(path, r.line, "utc",
                        "time " + t.text(r, cu) + " is not after the previous sample's (line " +
                            std::to_string(s.samples.back().line) + "); samples must be strictly increasing");
    s.samples.push_back(a);
  }
  if (s.samples.size() < 2)
    throw_input_error(
        path, t.records.empty() ? 1 : t.records.back().line, "utc",
        "at least 2 attitude samples are needed to interpolate, found " + std::to_string(s.samples.size()));
  return s;
}

AttitudeSeries read_attitude_csv(const std::string& path) {
  return parse_attitude_csv(read_file_text(path), path);
}

}  // namespace rangecal
