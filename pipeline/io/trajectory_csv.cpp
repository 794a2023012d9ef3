#include "pipeline/io/trajectory_csv.hpp"

#include <fmt/format.h>

#include <cmath>

#include "config/atomic_file.hpp"

namespace rangecal {

namespace {

constexpr const char* kTrajectoryHeader =
    "utc,E,N,U,lat,lon,h,sigma_E,sigma_N,sigma_U,cov_EN,cov_EU,cov_NU,sigma_m,sigma_labels_m,sigma_timing_m,"
    "sigma_calibration_m,vE,vN,vU,sigma_vE,sigma_vN,sigma_vU,cameras,rms_px,chi2,dof,inflated,extrapolated";

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

}  // namespace rangecal
