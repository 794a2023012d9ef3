#pragma once
// `rangecal project` (docs/cli.md) as functions: world points through a calibrated camera to pixels
// (`id,u,v`), the points given in site ENU (`id,E,N,U`, metres) or, when the camera's
// calibration names its site origin, as WGS84 geodetic coordinates (`id,lat,lon,h`). File I/O
// stays in the caller (pipeline/cli/project_command.cpp).
#include <string>

#include "gnss/geodesy/geodetic_origin.hpp"
#include "vision/camera/camera_model.hpp"

namespace rangecal {

/// Projects every record of the `id,E,N,U` CSV text (site ENU, metres) with `cam` and returns `id,u,v` CSV
/// text (header line, then one line per point, in input order; u, v in rangecal's pixels — centre of the
/// top-left pixel (0, 0), v down — with 6 decimals, i.e. 1e-6 px). `points_file` names the input in messages.
/// Throws rangecal::Error (kind input) naming the file, line and field for a missing column, a
/// non-numeric value, a point behind the camera (Zc ≤ 0) or a point where the distortion inverse
/// does not converge (the message also names `calibration_file`, the camera's file, when given).
std::string project_points_csv(const Camera& cam, const std::string& points_csv_text,
                               const std::string& points_file, const std::string& calibration_file = "");

/// As project_points_csv for `id,lat,lon,h` CSV text: WGS84 latitude and longitude in degrees,
/// ellipsoidal height in metres, converted to the site ENU frame about `origin`
/// (gnss/geodesy/local_enu.hpp, GeographicLib::LocalCartesian). A point outside the site box
/// (±50 km: a wrong origin or swapped lat/lon) is an input error naming the line.
std::string project_geodetic_points_csv(const Camera& cam, const GeodeticOrigin& origin,
                                        const std::string& points_csv_text, const std::string& points_file,
                                        const std::string& calibration_file = "");

}  // namespace rangecal
