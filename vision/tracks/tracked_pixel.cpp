#include "vision/tracks/tracked_pixel.hpp"

#include <algorithm>
#include <cctype>
#include <string>

#include "config/error.hpp"

namespace rangecal {

std::optional<double> track_coordinate(const CsvTable& t, const CsvRecord& r, std::size_t col) {
  std::string cell = t.text(r, col);
  std::transform(cell.begin(), cell.end(), cell.begin(), [](unsigned char c) { return std::tolower(c); });
  if (cell.empty() || cell == "nan") return std::nullopt;
  return t.number(r, col);
}

bool pixel_inside(const Eigen::Vector2d& uv, int width_px, int height_px) {
  return uv.x() >= -0.5 && uv.x() <= width_px - 0.5 && uv.y() >= -0.5 && uv.y() <= height_px - 0.5;
}

}  // namespace rangecal
