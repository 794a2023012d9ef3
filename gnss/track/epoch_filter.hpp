#pragma once
// Filtering of PPK epochs (docs/formats.md): epochs whose Q is not accepted, or whose sd exceeds
// max_sd_m in any of E, N, U, are dropped and counted; gaps longer than max_gap_s (across which
// nothing may be interpolated) are found and listed.
#include <cstddef>
#include <map>
#include <vector>

#include "gnss/time/utc_time.hpp"
#include "gnss/track/antenna_epochs.hpp"

namespace rangecal {

struct EpochFilterOptions {
  std::vector<int> accept_quality{1};  ///< Q values kept (1 fix … 6 ppp)
  double max_sd_m = 0.05;              ///< drop when any of sdE, sdN, sdU (epoch-local ENU) exceeds this
  double max_gap_s = 0.5;              ///< spacing above which consecutive epochs form a gap
};

struct EpochFilterCounts {
  std::size_t read = 0;                           ///< epochs in
  std::size_t kept = 0;                           ///< epochs out
  std::size_t dropped_quality = 0;                ///< Q not in accept_quality (checked first)
  std::size_t dropped_sd = 0;                     ///< accepted Q but an sd above max_sd_m
  std::map<int, std::size_t> read_by_quality;     ///< Q → epochs read
  std::map<int, std::size_t> dropped_by_quality;  ///< Q → epochs dropped for their Q
};

/// Keeps the epochs that pass (order preserved) and counts the rest by reason. An epoch dropped
/// for its Q is not also counted for its sd.
std::vector<AntennaEpoch> filter_epochs(std::vector<AntennaEpoch> in, const EpochFilterOptions& opt,
                                        EpochFilterCounts* counts);

/// A stretch with no epoch: consecutive epochs `from` and `to` more than max_gap_s apart.
struct TimeGap {
  UtcTime from;
  UtcTime to;
  double duration_s() const { return seconds_between(from, to); }
};

/// The gaps of a strictly increasing time sequence: every consecutive pair more than max_gap_s
/// apart (strictly greater), in time order.
std::vector<TimeGap> find_gaps(const std::vector<UtcTime>& times, double max_gap_s);

}  // namespace rangecal
