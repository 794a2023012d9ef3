#pragma once
// The HTML page of `rangecal compare-calibrations --html FILE`: the summary and the map of
// |q_B − q_A| over the image (colour map with contours, × where the difference exceeds the combined
// σ), and the difference vectors. Self-contained (inline CSS and SVG, no scripts), deterministic.
#include <string>

#include "pipeline/report/calibration_difference.hpp"

namespace rangecal {

/// `name_a`, `name_b` name the two calibrations (e.g. their files); `width_px`, `height_px` the image.
std::string render_difference_html(const CalibrationDifference& d, const std::string& name_a,
                                   const std::string& name_b, int width_px, int height_px);

}  // namespace rangecal
