#pragma once
// Import of a DLT-11 camera (DLTdv, Argus, easyWand; Abdel-Aziz & Karara 1971) into rangecal's
// model, the inverse of vision/camera/dlt_export.hpp's coefficients (without its undistortion
// profile: a DLT-11 is a pinhole).
//
// The coefficients map site ENU metres to the tools' pixel frame (origin at the image's
// bottom-left corner, y up, continuous; dlt_export.hpp):
//   x = (L1 X + L2 Y + L3 Z + L4) / (L9 X + L10 Y + L11 Z + 1),  y = (L5 … L8) / (same)
// so P = [L1 L2 L3 L4; L5 L6 L7 L8; L9 L10 L11 1] and, in rangecal's pixels (u = x − 0.5,
// v = H − 0.5 − y), P' = M·P with M = [1 0 −0.5; 0 −1 H − 0.5; 0 0 1], split into K, R and C
// and mapped onto rangecal's model as the DLT calibration method splits its own P
// (vision/calibration/dlt.hpp: seed 000 eqs. 3–6; Hartley & Zisserman 2004, §6.2.4). rangecal's
// model has no skew: what the dropped skew moves is measured over the image as the fit error (the
// pixel distance between the DLT's projection and rangecal's of the same ray).
#include <array>
#include <string>

#include "vision/camera/imported_camera.hpp"
#include "vision/camera/sensor_geometry.hpp"

namespace rangecal {

/// The camera of DLT coefficients L1 … L11 (the tools' pixel frame, site ENU metres) for `sensor`'s
/// image and pixel pitch. `skew_px` (out, optional) receives K's skew. Throws rangecal::Error
/// (calibration) when the coefficients are not finite, their left 3 × 3 block is singular (no
/// camera centre), the image size or the pitch is not positive, the aspect fx / fy lies outside
/// [0.5, 2] (not a camera's pixels), or the principal point lies off the image (coefficients of
/// another image height).
ImportedCamera camera_from_dlt(const std::array<double, 11>& L, const SensorGeometry& sensor,
                               double* skew_px = nullptr);

/// Reads camera `column` (1-based) of a DLTdv / Argus coefficient file: 11 non-blank lines, each
/// one coefficient per camera, comma separated, no header (dlt_export.hpp's
/// `dlt_coefficients_csv`). Throws rangecal::Error (input) naming the file when it is missing or has
/// fewer than 11 lines (the count), and its line and column when a line is short of the column, a
/// cell is not a finite number, or a 12th line follows.
std::array<double, 11> read_dlt_coefficients_csv(const std::string& path, int column);

}  // namespace rangecal
