#pragma once
// Plane-to-image homography by the normalised DLT (seed 001 eqs. 10–13; Hartley & Zisserman
// alg. 4.2): s·[u, v, 1]ᵀ = H·[X, Y, 1]ᵀ for model points (X, Y, 0) on a planar target.
// H = [h1 h2 h3] by columns (seed 001 eq. 5 as corrected in seeds/NOTES.md), scaled to ‖H‖_F = 1
// with H(2,2) ≥ 0.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "vision/calibration/point_correspondence.hpp"

namespace rangecal {

/// Needs ≥ 4 points with world Z = 0 (|Z| ≤ 1e-9·extent) not all on one line. Throws
/// rangecal::Error(calibration) naming the cause (too few points, NaN/inf, Z ≠ 0, collinear, singular).
/// `what` names the caller in messages (e.g. "planar view 3").
Eigen::Matrix3d fit_homography(const std::vector<PointCorrespondence>& pts,
                               const std::string& what = "homography");

}  // namespace rangecal
