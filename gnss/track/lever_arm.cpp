#include "gnss/track/lever_arm.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "config/physical_ranges.hpp"

namespace rangecal {

Eigen::Vector3d lamp_enu_full(const Eigen::Vector3d& antenna_enu, const Eigen::Matrix3d& R_nb,
                              const Eigen::Vector3d& lever_frd_m) {
  // seed 002 eq. 4 in NED, then NED → ENU (docs/conventions.md).
  return antenna_enu + ned_to_enu(R_nb * lever_frd_m);
}

Eigen::Vector3d lamp_enu_vertical(const Eigen::Vector3d& antenna_enu, double vertical_m) {
  return antenna_enu - Eigen::Vector3d(0, 0, vertical_m);  // seed 002 eq. 5
}

double vertical_form_error_m(const Eigen::Matrix3d& R_nb, double vertical_m) {
  return std::abs(vertical_m) * (R_nb.col(2) - Eigen::Vector3d::UnitZ()).norm();
}

std::optional<double> lever_motion_mps(const AttitudeSeries& att, UtcTime t,
                                       const Eigen::Vector3d& lever_frd_m, double max_gap_s) {
  constexpr std::int64_t kHalfStepNs = 20'000'000;
  const auto before = interpolate_attitude(att, UtcTime{t.ns - kHalfStepNs}, max_gap_s);
  const auto after = interpolate_attitude(att, UtcTime{t.ns + kHalfStepNs}, max_gap_s);
  if (!before || !after) return std::nullopt;
  return (rotation_nb(*after) * lever_frd_m - rotation_nb(*before) * lever_frd_m).norm() /
         (2 * static_cast<double>(kHalfStepNs) * 1e-9);
}

namespace {

/// The lamp hangs from the UAV that carries the antenna: the whole 3-D separation of the two marks,
/// not only its height, is within ranges::kMaxLeverArmM. The field named is the axis that carries
/// most of it.
void check_separation(const std::string& path, const std::string& id, long line,
                      const Eigen::Vector3d& antenna, const Eigen::Vector3d& lamp) {
  const Eigen::Vector3d d = lamp - antenna;
  if (d.norm() <= ranges::kMaxLeverArmM) return;
  Eigen::Index axis = 0;
  d.cwiseAbs().maxCoeff(&axis);
  static const char* const kAxis[] = {"E", "N", "U"};
  throw_input_error(path, line, kAxis[axis],
                    "session '" + id + "' puts the lamp mark " + format_number("%.3f", d.norm()) +
                        " m from the antenna mark (E " + format_number("%.3f", d.x()) + ", N " +
                        format_number("%.3f", d.y()) + ", U " + format_number("%.3f", d.z()) +
                        " m); the lamp hangs within 10 m of the antenna — a mark of another object or "
                        "another station set-up?");
}

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Sessions measure the same lever: a session whose offset is further than
/// ranges::kTotalStationAgreementM from the median of the others is a wrong mark or a misread
/// height, named with its value. With two sessions the wrong one cannot be told: both are named.
void check_sessions_agree(const std::string& path, const TotalStationOffset& t,
                          const std::vector<long>& lines) {
  const std::size_t n = t.per_session_m.size();
  if (n < 2) return;
  std::size_t worst = 0;
  double worst_dev = -1, worst_median = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<double> others;
    for (std::size_t j = 0; j < n; ++j)
      if (j != i) others.push_back(t.per_session_m[j]);
    const double m = median_of(others);
    const double dev = std::abs(t.per_session_m[i] - m);
    if (dev > worst_dev) {
      worst = i;
      worst_dev = dev;
      worst_median = m;
    }
  }
  if (worst_dev <= ranges::kTotalStationAgreementM) return;
  const std::string tolerance = format_number("%.0f", 100 * ranges::kTotalStationAgreementM) + " cm";
  if (n == 2)
    throw_input_error(path, lines[1], "U",
                      "sessions '" + t.sessions[0] + "' (" + format_number("%.4f", t.per_session_m[0]) +
                          " m) and '" + t.sessions[1] + "' (" + format_number("%.4f", t.per_session_m[1]) +
                          " m) disagree by " + format_number("%.1f", 100 * worst_dev) + " cm (more than " +
                          tolerance + "); which is wrong cannot be told from two: measure a third session");
  throw_input_error(
      path, lines[worst], "U",
      "session '" + t.sessions[worst] + "' gives " + format_number("%.4f", t.per_session_m[worst]) + " m, " +
          format_number("%.1f", 100 * worst_dev) + " cm from the median of the other sessions (" +
          format_number("%.4f", worst_median) + " m; they must agree within " + tolerance +
          "): a wrong mark or a misread height — remove or re-measure it");
}

}  // namespace

TotalStationOffset parse_total_station_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  // E and N are required by the format (and checked as numbers) though only U enters the offset.
  const std::size_t cs = t.column("session"), ct = t.column("target"), ce = t.column("E"), cn = t.column("N"),
                    cu = t.column("U");
  struct Session {
    long antenna_line = 0, lamp_line = 0;
    Eigen::Vector3d antenna = Eigen::Vector3d::Zero(), lamp = Eigen::Vector3d::Zero();  // ENU, m
  };
  std::vector<std::string> order;
  std::map<std::string, Session> sessions;
  for (const CsvRecord& r : t.records) {
    const std::string& id = t.text(r, cs);
    const std::string& target = t.text(r, ct);
    if (id.empty()) throw_input_error(path, r.line, "session", "empty session id");
    // Total-station coordinates in any local frame: only differences matter, so the check is on the
    // antenna–lamp difference below; the values themselves must be site-sized numbers.
    const double w = ranges::kSiteHalfWidthM;
    const double u = t.number_in(r, cu, -w, w, "total-station coordinate, m");
    const Eigen::Vector3d enu(t.number_in(r, ce, -w, w, "total-station coordinate, m"),
                              t.number_in(r, cn, -w, w, "total-station coordinate, m"), u);
    if (!sessions.count(id)) order.push_back(id);
    Session& s = sessions[id];
    if (target == "antenna") {
      if (s.antenna_line)
        throw_input_error(
            path, r.line, "target",
            "session '" + id + "' already has an antenna row (line " + std::to_string(s.antenna_line) + ")");
      s.antenna_line = r.line;
      s.antenna = enu;
    } else if (target == "lamp") {
      if (s.lamp_line)
        throw_input_error(
            path, r.line, "target",
            "session '" + id + "' already has a lamp row (line " + std::to_string(s.lamp_line) + ")");
      s.lamp_line = r.line;
      s.lamp = enu;
    } else {
      throw_input_error(path, r.line, "target",
                        "'" + target + "' is not a target (expected antenna or lamp)");
    }
  }
  if (order.empty())
    throw_input_error(path, 1, "session", "no survey rows (expected session,target,E,N,U rows)");
  TotalStationOffset out;
  std::vector<long> lamp_lines;
  for (const std::string& id : order) {
    const Session& s = sessions[id];
    if (!s.antenna_line || !s.lamp_line)
      throw_input_error(path, s.antenna_line ? s.antenna_line : s.lamp_line, "target",
                        "session '" + id + "' lacks its " + (s.antenna_line ? "lamp" : "antenna") + " row");
    check_separation(path, id, s.lamp_line, s.antenna, s.lamp);
    out.sessions.push_back(id);
    out.per_session_m.push_back(s.antenna.z() - s.lamp.z());
    lamp_lines.push_back(s.lamp_line);
  }
  check_sessions_agree(path, out, lamp_lines);
  const double n = static_cast<double>(out.per_session_m.size());
  double sum = 0;
  for (double d : out.per_session_m) sum += d;
  out.vertical_m = sum / n;
  double ss = 0;
  for (double d : out.per_session_m) ss += (d - out.vertical_m) * (d - out.vertical_m);
  out.sd_m = out.per_session_m.size() > 1 ? std::sqrt(ss / (n - 1)) : 0.0;
  return out;
}

TotalStationOffset read_total_station_csv(const std::string& path) {
  return parse_total_station_csv(read_file_text(path), path);
}

}  // namespace rangecal
