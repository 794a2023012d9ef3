#include "pipeline/report/correction_autocorrelation.hpp"

#include <algorithm>
#include <cmath>

namespace rangecal {

std::vector<AutocorrelationBin> empirical_autocorrelation(const std::vector<double>& t_s,
                                                          const std::vector<std::vector<double>>& series,
                                                          double bin_s, double max_lag_s) {
  const std::size_t n_bins = static_cast<std::size_t>(std::floor(max_lag_s / bin_s)) + 1;
  std::vector<double> product(n_bins, 0), lag(n_bins, 0);
  std::vector<long> pairs(n_bins, 0);
  double sum_sq = 0;
  long n = 0;
  const double reach = (static_cast<double>(n_bins) - 0.5) * bin_s;  // the last bin's upper edge
  for (const std::vector<double>& x : series) {
    double sum = 0;
    long m = 0;
    for (std::size_t i = 0; i < x.size() && i < t_s.size(); ++i)
      if (std::isfinite(x[i])) sum += x[i], ++m;
    if (m == 0) continue;
    const double mean = sum / static_cast<double>(m);
    for (std::size_t i = 0; i < x.size() && i < t_s.size(); ++i) {
      if (!std::isfinite(x[i])) continue;
      sum_sq += (x[i] - mean) * (x[i] - mean);
      ++n;
      for (std::size_t j = i + 1; j < x.size() && j < t_s.size() && t_s[j] - t_s[i] < reach; ++j) {
        if (!std::isfinite(x[j])) continue;
        const double dt = t_s[j] - t_s[i];
        const std::size_t k = static_cast<std::size_t>(std::floor(dt / bin_s + 0.5));
        product[k] += (x[i] - mean) * (x[j] - mean);
        lag[k] += dt;
        ++pairs[k];
      }
    }
  }
  std::vector<AutocorrelationBin> out;
  if (!(sum_sq > 0)) return out;
  const double variance = sum_sq / static_cast<double>(n);
  for (std::size_t k = 0; k < n_bins; ++k) {
    if (pairs[k] == 0) continue;
    const double p = static_cast<double>(pairs[k]);
    out.push_back({lag[k] / p, product[k] / p / variance, pairs[k]});
  }
  return out;
}

double model_autocorrelation(double gm_sd_m, double tau_s, double white_sd_m, double lag_s) {
  if (!(gm_sd_m > 0) || !(tau_s > 0)) return 0;
  const double g2 = gm_sd_m * gm_sd_m;
  return g2 * gauss_markov_transition(lag_s, tau_s) / (white_sd_m * white_sd_m + g2);
}

AutocorrelationLags autocorrelation_lags(const PpkErrorModel& m, const std::vector<double>& t_s) {
  AutocorrelationLags l;
  l.max_lag_s = m.correlated() ? std::min(3 * std::max(m.tau_h_s, m.tau_v_s), 120.0) : 30.0;
  std::vector<double> steps;
  for (std::size_t k = 1; k < t_s.size(); ++k) steps.push_back(t_s[k] - t_s[k - 1]);
  double median_step = 0;
  if (!steps.empty()) {
    std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2),
                     steps.end());
    median_step = steps[steps.size() / 2];
  }
  l.bin_s = std::max(l.max_lag_s / 40, median_step);
  return l;
}

}  // namespace rangecal
