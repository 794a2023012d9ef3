#include "gnss/track/lever_arm.hpp"

#include <cmath>
#include <map>

#include "config/csv_table.hpp"
#include "config/error.hpp"
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

TotalStationOffset parse_total_station_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  // E and N are required by the format (and checked as numbers) though only U enters the offset.
  const std::size_t cs = t.column("session"), ct = t.column("target"), ce = t.column("E"), cn = t.column("N"),
                    cu = t.column("U");
  struct Session {
    long antenna_line = 0, lamp_line = 0;
    double u_antenna = 0, u_lamp = 0;
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
    t.number_in(r, ce, -w, w, "total-station coordinate, m");
    t.number_in(r, cn, -w, w, "total-station coordinate, m");
    if (!sessions.count(id)) order.push_back(id);
    Session& s = sessions[id];
    if (target == "antenna") {
      if (s.antenna_line)
        throw_input_error(
            path, r.line, "target",
            "session '" + id + "' already has an antenna row (line " + std::to_string(s.antenna_line) + ")");
      s.antenna_line = r.line;
      s.u_antenna = u;
    } else if (target == "lamp") {
      if (s.lamp_line)
        throw_input_error(
            path, r.line, "target",
            "session '" + id + "' already has a lamp row (line " + std::to_string(s.lamp_line) + ")");
      s.lamp_line = r.line;
      s.u_lamp = u;
    } else {
      throw_input_error(path, r.line, "target",
                        "'" + target + "' is not a target (expected antenna or lamp)");
    }
  }
  if (order.empty())
    throw_input_error(path, 1, "session", "no survey rows (expected session,target,E,N,U rows)");
  TotalStationOffset out;
  for (const std::string& id : order) {
    const Session& s = sessions[id];
    if (!s.antenna_line || !s.lamp_line)
      throw_input_error(path, s.antenna_line ? s.antenna_line : s.lamp_line, "target",
                        "session '" + id + "' lacks its " + (s.antenna_line ? "lamp" : "antenna") + " row");
    const double d = s.u_antenna - s.u_lamp;
    if (std::abs(d) > ranges::kMaxLeverArmM)
      throw_input_error(path, s.lamp_line, "U",
                        "session '" + id + "' puts the lamp " + std::to_string(d) +
                            " m below the antenna; the lamp hangs within 10 m of the antenna (as "
                            "vertical_m in the mission config)");
    out.sessions.push_back(id);
    out.per_session_m.push_back(d);
  }
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
