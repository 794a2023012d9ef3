#pragma once
// `gnss/lamp_track_adjusted.csv` (the network bundle's lamp track, docs/optimisation.md "Network
// bundle"): one row per lamp epoch the network used, in time order —
// `utc,E,N,U,sdE,sdN,sdU,dE,dN,dU,flag`: the adjusted position (ENU m, 0.1 mm), its 1σ (from the
// joint covariance, cameras included), the correction adjusted − PPK fix, and `flag` = 1 for a PPK
// outlier (prior dropped), else 0. Written by the calibrate stage, read by the report stage.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"
#include "gnss/track/lamp_track.hpp"
#include "optim/network/network_result.hpp"

namespace rangecal {

/// One row of the file.
struct LampTrackAdjustedRow {
  UtcTime utc;
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();         ///< adjusted E, N, U (m)
  Eigen::Vector3d sd_enu = Eigen::Vector3d::Zero();      ///< its 1σ per axis (m)
  Eigen::Vector3d correction = Eigen::Vector3d::Zero();  ///< dE, dN, dU = adjusted − PPK fix (m)
  bool flagged = false;                                  ///< a PPK outlier: its prior was dropped
  long line = 0;                                         ///< line in the file when read
};

/// `epoch_of_point[k]` is point k's index in `track` (−1: not an epoch).
std::string format_lamp_track_adjusted_csv(const LampTrack& track, const NetworkResult& r,
                                           const std::vector<long>& epoch_of_point);

/// Parses the file's text; `path` names it in messages. Throws rangecal::Error (input) naming file,
/// line and field for a missing column, a UTC that does not parse or does not follow the previous
/// row's, a non-numeric value, a negative σ, or a flag other than 0 / 1.
std::vector<LampTrackAdjustedRow> parse_lamp_track_adjusted_csv(const std::string& text,
                                                                const std::string& path);
/// Reads the file (a missing file is an input error naming it).
std::vector<LampTrackAdjustedRow> read_lamp_track_adjusted_csv(const std::string& path);

}  // namespace rangecal
