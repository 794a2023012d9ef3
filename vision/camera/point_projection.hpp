#pragma once
// `rangecal project` (SPEC §6) as a function: world points (`id,E,N,U` CSV, ENU metres) through a
// calibrated camera to pixels (`id,u,v`). File I/O stays in the caller (pipeline/cli/project_command.cpp).
#include <string>

#include "vision/camera/camera_model.hpp"

namespace rangecal {

/// Projects every record of the `id,E,N,U` CSV text with `cam` and returns `id,u,v` CSV text
/// (header line, then one line per point, in input order; u, v with 6 decimals, i.e. 1e-6 px).
/// `points_file` names the input in messages. Throws rangecal::Error (kind input) naming the file,
/// line and field for a missing column, a non-numeric value, a point behind the camera (Zc ≤ 0)
/// or a point where the distortion inverse does not converge.
std::string project_points_csv(const Camera& cam, const std::string& points_csv_text,
                               const std::string& points_file);

}  // namespace rangecal
