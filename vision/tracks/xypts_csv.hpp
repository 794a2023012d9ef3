#pragma once
// DLTdv / Argus 2-D points, `xypts.csv` (Hedrick 2008, "Software techniques for two- and three-dimensional
// kinematic measurements of biological and biomimetic systems", Bioinspiration & Biomimetics 3;
// Jackson et al. 2016, "3D for the people", J. Exp. Biol. 219): header
// `pt1_cam1_X,pt1_cam1_Y,pt1_cam2_X,…`, then one row per frame, data row k being frame k (1-based);
// `NaN` or a blank cell where the point was not digitised. Coordinates are MATLAB's: the first pixel's
// centre is 1, and Y counts from the bottom row (DLTdv5–7, Argus) or the top (DLTdv8) — the file does
// not say which, so TrackReadOptions::y_origin must. Mapping to rangecal's pixels (top-left pixel's
// centre at 0, v down, H the image height):
//   u = X − 1;   v = Y − 1 (top)   or   v = H − Y (bottom)
#include <string>

#include "vision/tracks/image_track.hpp"
#include "vision/tracks/track_read_options.hpp"

namespace rangecal {

/// True when `header_line` starts with a `pt<n>_cam<m>_X` column.
bool is_xypts_header(const std::string& header_line);

/// The track of point options.point in camera options.camera. Throws rangecal::Error (input) naming
/// the file, line and column; (input, line 1) when the file has no such columns or y_origin is unset.
ImageTrack parse_xypts_csv(const std::string& text, const std::string& path, const TrackReadOptions& options);

}  // namespace rangecal
