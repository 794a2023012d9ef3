#include "vision/calibration/image_coverage.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rangecal {

ImageCoverage::ImageCoverage(const std::vector<Eigen::Vector2d>& pixels, double cell_px) : cell_px_(cell_px) {
  for (const Eigen::Vector2d& p : pixels)
    if (p.allFinite())
      cells_.emplace(static_cast<long>(std::floor(p.x() / cell_px_)),
                     static_cast<long>(std::floor(p.y() / cell_px_)));
}

bool ImageCoverage::covers(const Eigen::Vector2d& uv_px) const {
  if (cells_.empty()) return true;
  if (!uv_px.allFinite()) return false;
  const long cu = static_cast<long>(std::floor(uv_px.x() / cell_px_));
  const long cv = static_cast<long>(std::floor(uv_px.y() / cell_px_));
  for (long du = -1; du <= 1; ++du)
    for (long dv = -1; dv <= 1; ++dv)
      if (cells_.count({cu + du, cv + dv})) return true;
  return false;
}

double ImageCoverage::distance_outside_px(const Eigen::Vector2d& uv_px) const {
  if (covers(uv_px)) return 0;
  if (!uv_px.allFinite()) return std::numeric_limits<double>::infinity();
  // Each covered cell with its neighbours is a box of three cells a side; the distance to the
  // nearest box.
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [cu, cv] : cells_) {
    const double u0 = static_cast<double>(cu - 1) * cell_px_, u1 = static_cast<double>(cu + 2) * cell_px_;
    const double v0 = static_cast<double>(cv - 1) * cell_px_, v1 = static_cast<double>(cv + 2) * cell_px_;
    const double du = std::max({u0 - uv_px.x(), 0.0, uv_px.x() - u1});
    const double dv = std::max({v0 - uv_px.y(), 0.0, uv_px.y() - v1});
    best = std::min(best, std::hypot(du, dv));
  }
  return best;
}

}  // namespace rangecal
