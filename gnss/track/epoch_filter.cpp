#include "gnss/track/epoch_filter.hpp"

#include <algorithm>
#include <cmath>

namespace rangecal {

std::vector<AntennaEpoch> filter_epochs(std::vector<AntennaEpoch> in, const EpochFilterOptions& opt,
                                        EpochFilterCounts* counts) {
  EpochFilterCounts c;
  bool accept[8] = {false};
  for (int q : opt.accept_quality)
    if (q >= 0 && q < 8) accept[q] = true;
  // Compacted in place: a second vector of a long file's epochs costs more in fresh-page faults
  // than the filtering itself.
  std::size_t kept = 0;
  for (const AntennaEpoch& e : in) {
    ++c.read;
    ++c.read_by_quality[e.quality];
    if (e.quality < 0 || e.quality >= 8 || !accept[e.quality]) {
      ++c.dropped_quality;
      ++c.dropped_by_quality[e.quality];
      continue;
    }
    if (!(e.sd_local.maxCoeff() <= opt.max_sd_m)) {  // NaN sd drops too
      ++c.dropped_sd;
      continue;
    }
    in[kept++] = e;
  }
  in.resize(kept);
  c.kept = kept;
  if (counts) *counts = c;
  return in;
}

std::vector<TimeGap> find_gaps(const std::vector<UtcTime>& times, double max_gap_s) {
  // Compare in integer ns so that a spacing of exactly max_gap_s is not a gap.
  const auto limit_ns = static_cast<std::int64_t>(std::llround(max_gap_s * 1e9));
  std::vector<TimeGap> gaps;
  for (std::size_t i = 1; i < times.size(); ++i)
    if (times[i].ns - times[i - 1].ns > limit_ns) gaps.push_back({times[i - 1], times[i]});
  return gaps;
}

}  // namespace rangecal
