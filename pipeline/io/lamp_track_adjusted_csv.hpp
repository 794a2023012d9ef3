#pragma once
// `gnss/lamp_track_adjusted.csv` (the network bundle's lamp track): one row per lamp epoch the
// network used — `utc,E,N,U,sdE,sdN,sdU,dE,dN,dU,flag`: the adjusted position (ENU m, 0.1 mm), its
// 1σ (from the joint covariance, cameras included), the correction adjusted − PPK fix, and `flag`
// = 1 for a PPK outlier (prior dropped), else 0.
#include <string>
#include <vector>

#include "gnss/track/lamp_track.hpp"
#include "optim/network/network_adjustment.hpp"

namespace rangecal {

/// `epoch_of_point[k]` is point k's index in `track` (−1: not an epoch).
std::string format_lamp_track_adjusted_csv(const LampTrack& track, const NetworkResult& r,
                                           const std::vector<long>& epoch_of_point);

}  // namespace rangecal
