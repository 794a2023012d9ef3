#include "vision/calibration/image_coverage.hpp"

#include <cmath>

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

}  // namespace rangecal
