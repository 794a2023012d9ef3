#include "pipeline/io/trajectory_csv.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "gnss/time/csv_utc.hpp"

namespace rangecal {

namespace {

constexpr const char* kTrajectoryHeader =
    "utc,E,N,U,lat,lon,h,sigma_E,sigma_N,sigma_U,cov_EN,cov_EU,cov_NU,sigma_m,sigma_labels_m,sigma_timing_m,"
    "sigma_calibration_m,vE,vN,vU,sigma_vE,sigma_vN,sigma_vU,aE,aN,aU,sigma_aE,sigma_aN,sigma_aU,cameras,rms_"
    "px,chi2,"
    "dof,inflated,extrapolated";

// A number with `digits` decimals; "-0.000…" printed without its sign; blank for NaN.
void cell(std::string* s, double v, int digits) {
  s->push_back(',');
  if (!std::isfinite(v)) return;
  std::string text = fmt::format("{:.{}f}", v, digits);
  if (text.find_first_not_of("-0.") == std::string::npos && text[0] == '-') text.erase(0, 1);
  *s += text;
}

double root_trace(const Eigen::Matrix3d& c) {
  return std::sqrt(std::max(0.0, c.trace()));
}

}  // namespace

std::string format_trajectory_csv(const Trajectory& trajectory, const LocalEnu& site) {
  std::string s = std::string(kTrajectoryHeader) + "\n";
  for (const TrajectoryPoint& p : trajectory.points) {
    const TriangulationResult& f = p.fix;
    s += format_iso8601_utc(p.t);
    for (int k = 0; k < 3; ++k) cell(&s, f.point[k], 4);
    const Eigen::Vector3d llh = site.to_geodetic(f.point);
    cell(&s, llh.x(), 9);
    cell(&s, llh.y(), 9);
    cell(&s, llh.z(), 4);
    for (int k = 0; k < 3; ++k) cell(&s, std::sqrt(std::max(0.0, f.cov_m2(k, k))), 4);
    cell(&s, f.cov_m2(0, 1), 8);
    cell(&s, f.cov_m2(0, 2), 8);
    cell(&s, f.cov_m2(1, 2), 8);
    cell(&s, f.sigma_m, 4);
    cell(&s, root_trace(f.cov_pick_m2), 4);
    cell(&s, root_trace(f.cov_timing_m2), 4);
    cell(&s, root_trace(f.cov_calibration_m2), 4);
    for (int k = 0; k < 3; ++k) cell(&s, p.velocity[k], 3);
    for (int k = 0; k < 3; ++k) cell(&s, p.velocity_sd[k], 3);
    for (int k = 0; k < 3; ++k) cell(&s, p.acceleration[k], 3);
    for (int k = 0; k < 3; ++k) cell(&s, p.acceleration_sd[k], 3);
    s.push_back(',');
    for (std::size_t i = 0; i < p.cameras.size(); ++i) s += (i ? "+" : "") + p.cameras[i];
    cell(&s, f.rms_px, 3);
    cell(&s, p.chi2, 2);
    s += "," + std::to_string(p.dof) + (p.inflated ? ",1" : ",0");
    s.push_back(',');
    for (std::size_t i = 0; i < p.extrapolated.size(); ++i) s += (i ? "+" : "") + p.extrapolated[i];
    s += "\n";
  }
  return s;
}

void write_trajectory_csv(const std::string& path, const Trajectory& trajectory, const LocalEnu& site) {
  write_file_atomic(path, format_trajectory_csv(trajectory, site));
}

namespace {

/// The ids of a `+`-joined cell in column `col`; none when blank. An empty or repeated id is an
/// input error naming the cell.
std::vector<std::string> camera_ids(const CsvTable& t, const CsvRecord& r, std::size_t col) {
  std::vector<std::string> ids;
  const std::string& cell = t.text(r, col);
  if (cell.empty()) return ids;
  for (const std::string& id : split_trim(cell, '+')) {
    if (id.empty() || std::find(ids.begin(), ids.end(), id) != ids.end())
      throw_input_error(t.path, r.line, t.header[col],
                        "'" + cell + "' is not camera ids joined by '+' (an id empty or given twice)");
    ids.push_back(id);
  }
  return ids;
}

}  // namespace

std::vector<TrajectoryRow> parse_trajectory_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t utc = t.column("utc"), cameras = t.column("cameras"), rms = t.column("rms_px"),
                    inflated = t.column("inflated"), extrapolated = t.column("extrapolated");
  const std::size_t enu[3] = {t.column("E"), t.column("N"), t.column("U")};
  const std::size_t sd[3] = {t.column("sigma_E"), t.column("sigma_N"), t.column("sigma_U")};
  const std::size_t en = t.column("cov_EN"), eu = t.column("cov_EU"), nu = t.column("cov_NU");
  const std::size_t total = t.column("sigma_m"), labels = t.column("sigma_labels_m"),
                    timing = t.column("sigma_timing_m"), calibration = t.column("sigma_calibration_m");
  std::vector<TrajectoryRow> rows;
  for (const CsvRecord& r : t.records) {
    TrajectoryRow row;
    row.utc = csv_utc(t, r, utc);
    if (!rows.empty() && !(rows.back().utc < row.utc))
      throw_input_error(path, r.line, "utc",
                        "not after the previous row's: the instants must be in time order");
    const std::array<double, 3> p = t.site_enu(r, enu[0], enu[1], enu[2]);
    row.enu = Eigen::Vector3d(p[0], p[1], p[2]);
    for (int k = 0; k < 3; ++k) {
      const double s = t.number_in(r, sd[k], 0, 1e6, "a 1σ in metres");
      row.cov_m2(k, k) = s * s;
    }
    row.cov_m2(0, 1) = row.cov_m2(1, 0) = t.number(r, en);
    row.cov_m2(0, 2) = row.cov_m2(2, 0) = t.number(r, eu);
    row.cov_m2(1, 2) = row.cov_m2(2, 1) = t.number(r, nu);
    // |ρ| ≤ 1, allowing for the σ columns' rounding to 0.1 mm.
    for (const auto& [i, j, col] : {std::tuple{0, 1, en}, std::tuple{0, 2, eu}, std::tuple{1, 2, nu}}) {
      const double bound = (std::sqrt(row.cov_m2(i, i)) + 0.5e-4) * (std::sqrt(row.cov_m2(j, j)) + 0.5e-4);
      if (std::abs(row.cov_m2(i, j)) > bound + 1e-8)
        throw_input_error(path, r.line, t.header[col],
                          "a covariance whose correlation exceeds 1 in magnitude");
    }
    row.sigma_m = t.number_in(r, total, 0, 1e6, "a 1σ in metres");
    row.sigma_labels_m = t.number_in(r, labels, 0, 1e6, "a 1σ in metres");
    row.sigma_timing_m = t.number_in(r, timing, 0, 1e6, "a 1σ in metres");
    row.sigma_calibration_m = t.number_in(r, calibration, 0, 1e6, "a 1σ in metres");
    row.cameras = camera_ids(t, r, cameras);
    row.rms_px = t.number_in(r, rms, 0, 1e9, "a reprojection rms in pixels");
    const std::int64_t flag = t.integer(r, inflated);
    if (flag != 0 && flag != 1) throw_input_error(path, r.line, "inflated", "expected 0 or 1");
    row.inflated = flag == 1;
    row.extrapolated = camera_ids(t, r, extrapolated);
    rows.push_back(row);
  }
  return rows;
}

std::vector<TrajectoryRow> read_trajectory_csv(const std::string& path) {
  return parse_trajectory_csv(read_file_text(path), path);
}

}  // namespace rangecal
