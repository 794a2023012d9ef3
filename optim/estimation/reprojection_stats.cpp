#include "optim/estimation/reprojection_stats.hpp"

#include <algorithm>
#include <cmath>

namespace rangecal {

ReprojectionStats reprojection_stats(const std::vector<Eigen::Vector2d>& residual_px,
                                     const std::vector<char>& used) {
  ReprojectionStats stats;
  double sum_squares = 0, sum = 0, largest = 0;
  int n_used = 0;
  for (std::size_t i = 0; i < residual_px.size(); ++i) {
    if (!used[i]) continue;
    const double e = residual_px[i].norm();
    sum_squares += e * e;
    sum += e;
    largest = std::max(largest, e);
    ++n_used;
  }
  stats.n_used = n_used;
  stats.n_rejected = static_cast<int>(residual_px.size()) - n_used;
  if (n_used > 0) {
    stats.rms_px = std::sqrt(sum_squares / n_used);
    stats.mean_px = sum / n_used;
    stats.max_px = largest;
  }
  return stats;
}

}  // namespace rangecal
