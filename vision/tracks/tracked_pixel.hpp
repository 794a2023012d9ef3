#pragma once
// The rules every track reader shares, written once: a coordinate cell that may be empty (the target
// not seen) and a pixel that must lie inside the image.
#include <Eigen/Core>
#include <optional>

#include "config/csv_table.hpp"

namespace rangecal {

/// The number in column `col` of `r`, or nullopt when the cell is blank or NaN (any case): the target
/// was not labelled there. Any other text that is not a finite number throws rangecal::Error (input)
/// naming the file, line and column.
std::optional<double> track_coordinate(const CsvTable& t, const CsvRecord& r, std::size_t col);

/// True when `uv` (rangecal's pixels) lies inside a width × height image (pixel centres 0 … width − 1;
/// the image reaches half a pixel beyond). A tracker may place a label just beyond the edge (the
/// target half out of view); the readers keep such labels out and list their lines.
bool pixel_inside(const Eigen::Vector2d& uv, int width_px, int height_px);

}  // namespace rangecal
