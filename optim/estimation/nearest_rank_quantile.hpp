#pragma once
// The q-quantile of a sample by the nearest rank (Hyndman & Fan 1996, definition 1): the smallest
// value with at least a fraction q of the sample at or below it — always a member of the sample, so
// a table's "95 %" is a value that occurred. Used by the summaries of trajectories and plans.
#include <algorithm>
#include <cmath>
#include <vector>

namespace rangecal {

/// The q-quantile (q in [0, 1]) of `v` by the nearest rank, ⌈q·n⌉-th smallest (the smallest for
/// q = 0); `if_empty` for an empty `v`. Takes `v` by value: it is sorted.
inline double nearest_rank_quantile(std::vector<double> v, double q, double if_empty) {
  if (v.empty()) return if_empty;
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, k == 0 ? 0 : k - 1)];
}

}  // namespace rangecal
