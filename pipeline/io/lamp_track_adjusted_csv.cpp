#include "pipeline/io/lamp_track_adjusted_csv.hpp"

#include <cmath>
#include <cstdio>
#include <map>

namespace rangecal {

std::string format_lamp_track_adjusted_csv(const LampTrack& track, const NetworkResult& r,
                                           const std::vector<long>& epoch_of_point) {
  std::map<long, std::size_t> rows;  // epoch → point, in time order
  for (std::size_t k = 0; k < epoch_of_point.size() && k < r.points.size(); ++k)
    if (epoch_of_point[k] >= 0 && r.points[k].used) rows[epoch_of_point[k]] = k;
  std::string out = "utc,E,N,U,sdE,sdN,sdU,dE,dN,dU,flag\n";
  char buf[320];
  for (const auto& [e, k] : rows) {
    const NetworkPointResult& p = r.points[k];
    const Eigen::Vector3d sd = p.cov.diagonal().cwiseMax(0.0).cwiseSqrt();
    std::snprintf(buf, sizeof buf, "%s,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%d\n",
                  format_iso8601_utc(track.epochs[static_cast<std::size_t>(e)].utc).c_str(), p.enu.x(),
                  p.enu.y(), p.enu.z(), sd.x(), sd.y(), sd.z(), p.correction.x(), p.correction.y(),
                  p.correction.z(), p.ppk_outlier ? 1 : 0);
    out += buf;
  }
  return out;
}

}  // namespace rangecal
