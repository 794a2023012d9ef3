#include "optim/estimation/robust_scale.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace rangecal {

double robust_scale(std::vector<double> norms) {
  if (norms.empty()) return 1.0;
  std::nth_element(norms.begin(), norms.begin() + norms.size() / 2, norms.end());
  return norms[norms.size() / 2] / std::sqrt(2 * std::log(2.0));
}

double robust_outlier_threshold(double k, std::vector<double> norms) {
  return k * std::max(1.0, robust_scale(std::move(norms)));
}

}  // namespace rangecal
