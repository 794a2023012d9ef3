#include "gnss/track/attitude.hpp"

#include <algorithm>
#include <cmath>

#include "config/csv_table.hpp"
#include "config/error.hpp"

namespace rangecal {
namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
}

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
    std::string why;
    const auto utc = parse_iso8601_utc(t.text(r, cu), &why);
    if (!utc) throw_input_error(path, r.line, "utc", "'" + t.text(r, cu) + "': " + why);
    a.utc = *utc;
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

double wrap_deg_180(double a) {
  double r = std::fmod(a, 360.0);
  if (r <= -180.0) r += 360.0;
  if (r > 180.0) r -= 360.0;
  return r;
}

std::optional<Attitude> interpolate_attitude(const AttitudeSeries& s, UtcTime t, double max_gap_s) {
  const auto& v = s.samples;
  if (v.empty() || t < v.front().utc || t > v.back().utc) return std::nullopt;
  auto it =
      std::upper_bound(v.begin(), v.end(), t, [](UtcTime x, const AttitudeSample& a) { return x < a.utc; });
  if (it == v.end()) {  // t is exactly the last sample
    Attitude a = v.back().att;
    a.yaw_deg = wrap_deg_180(a.yaw_deg);
    return a;
  }
  const AttitudeSample& b = *it;
  const AttitudeSample& a = *(it - 1);
  const std::int64_t span = b.utc.ns - a.utc.ns;
  if (static_cast<double>(span) * 1e-9 > max_gap_s) return std::nullopt;
  // Fraction from integer ns: exact enough (span < 2^53 ns).
  const double f = static_cast<double>(t.ns - a.utc.ns) / static_cast<double>(span);
  Attitude r;
  r.roll_deg = a.att.roll_deg + f * (b.att.roll_deg - a.att.roll_deg);
  r.pitch_deg = a.att.pitch_deg + f * (b.att.pitch_deg - a.att.pitch_deg);
  // Yaw along the shorter arc: 179° → −179° passes through 180°, not through 0°.
  const double dyaw = wrap_deg_180(b.att.yaw_deg - a.att.yaw_deg);
  r.yaw_deg = wrap_deg_180(a.att.yaw_deg + f * dyaw);
  return r;
}

Eigen::Matrix3d rotation_nb(const Attitude& a) {
  const double cr = std::cos(a.roll_deg * kDeg), sr = std::sin(a.roll_deg * kDeg);
  const double cp = std::cos(a.pitch_deg * kDeg), sp = std::sin(a.pitch_deg * kDeg);
  const double cy = std::cos(a.yaw_deg * kDeg), sy = std::sin(a.yaw_deg * kDeg);
  Eigen::Matrix3d Rz, Ry, Rx;
  Rz << cy, -sy, 0, sy, cy, 0, 0, 0, 1;
  Ry << cp, 0, sp, 0, 1, 0, -sp, 0, cp;
  Rx << 1, 0, 0, 0, cr, -sr, 0, sr, cr;
  return Rz * Ry * Rx;  // SPEC §2; seed 002 eq. 3 with φ = yaw, θ = pitch, ψ = roll
}

}  // namespace rangecal
