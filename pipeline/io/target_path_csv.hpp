#pragma once
// A planned target path for `rangecal plan --target-path` (docs/accuracy_analysis.md "A target's
// path"): CSV with header `t_s,E,N,U` — time since the path's start (s, strictly increasing) and
// the target's position in the scenario's site ENU (m) — one row per waypoint; the target moves in
// a straight line at constant speed between consecutive waypoints.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace rangecal {

struct TargetPathPoint {
  double t_s = 0;                                   ///< s since the path's start
  Eigen::Vector3d enu_m = Eigen::Vector3d::Zero();  ///< site ENU (m)
  long line = 0;                                    ///< its line in the file
};

/// Parses the CSV text; `path` names it in messages. Throws rangecal::Error (input) naming the
/// file, line and column of a missing column, a bad cell, a time not after the previous row's, or
/// fewer than two rows.
std::vector<TargetPathPoint> parse_target_path_csv(const std::string& text, const std::string& path);
std::vector<TargetPathPoint> read_target_path_csv(const std::string& path);

}  // namespace rangecal
