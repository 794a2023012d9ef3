#pragma once
// Checks shared by the calibration initialisers (DLT, Tsai, planar): every degenerate input is a
// rangecal::Error of kind calibration (exit 4) whose field names the method and whose reason
// names the cause (docs/cli.md, docs/accuracy_analysis.md, Quality bars "degenerate geometry gives a clear
// error").
#include <string>
#include <vector>

#include "vision/calibration/point_correspondence.hpp"

namespace rangecal {

/// Shape of a world point set, from the singular values s0 ≥ s1 ≥ s2 of the centred coordinates.
enum class PointGeometry { single_point, collinear, coplanar, general };

/// Classifies with relative tolerance `rel_tol` on s1/s0 (collinear) and s2/s0 (coplanar).
PointGeometry classify_world_geometry(const std::vector<PointCorrespondence>& pts, double rel_tol = 1e-7);

/// Throws (calibration) if any coordinate is NaN or infinite, naming the point index.
void require_finite(const std::vector<PointCorrespondence>& pts, const std::string& method);

/// Throws (calibration) if pts.size() < n, saying how many unknowns need how many points.
void require_min_points(const std::vector<PointCorrespondence>& pts, std::size_t n, const std::string& method,
                        const std::string& why);

/// Throws (calibration) if the points are all one point or on one line; if `need_non_coplanar`,
/// also if they lie on one plane.
void require_world_geometry(const std::vector<PointCorrespondence>& pts, bool need_non_coplanar,
                            const std::string& method);

}  // namespace rangecal
