#pragma once
// The lamp track: the gnss stage's output (docs/gnss.md, docs/outputs.md `gnss/lamp_track.csv`) and the align
// stage's input. Positions are the lamp centre (antenna + lever arm) in local ENU metres about
// site.origin; times are UTC.
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

struct LampEpoch {
  UtcTime utc;
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();     ///< lamp centre, ENU metres
  Eigen::Vector3d sd_enu = Eigen::Vector3d::Zero();  ///< 1σ of E, N, U (m), from the .pos sd columns
  int quality = 0;                                   ///< RTKLIB Q (1 fix … 6 ppp)
  /// Velocity ENU (m/s) when the .pos file carries velocity columns; otherwise NaN (the align
  /// stage then estimates it from neighbouring epochs).
  Eigen::Vector3d vel_enu = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  /// Full covariance of E, N, U (m²): the .pos sd and sdne/sdeu/sdun columns rotated to site ENU
  /// (+ the lever arm's vertical variance), through lamp_track.csv's sd and correlation columns;
  /// NaN when not known (a track file without correlations) — the network bundle then uses
  /// diag(sd_enu²).
  Eigen::Matrix3d cov_enu = Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
};

/// Epochs strictly increasing in time. Gaps (consecutive epochs farther apart than the config's
/// max_gap_s) are not marked here: interpolation checks the spacing itself.
struct LampTrack {
  std::vector<LampEpoch> epochs;
};

}  // namespace rangecal
