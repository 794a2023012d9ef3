// The PPK corrections' autocorrelation (pipeline/report/correction_autocorrelation.hpp): on AR(1)
// series of known φ the estimate equals the textbook sample autocorrelation computed here and lies
// within its sampling error of φ^lag; on an irregularly sampled Gauss–Markov process plus white
// noise it follows the model's σ_g²·exp(−lag/τ)/(σ_w² + σ_g²); pairs across a gap longer than the
// largest lag are never formed; a hand-worked series gives its exact values.
#include "pipeline/report/correction_autocorrelation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace rangecal {
namespace {

// x_k = φ·x_{k−1} + √(1 − φ²)·ν_k, unit variance, stationary from the start.
std::vector<double> ar1(double phi, std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> z;
  std::vector<double> x(n);
  x[0] = z(rng);
  for (std::size_t k = 1; k < n; ++k) x[k] = phi * x[k - 1] + std::sqrt(1 - phi * phi) * z(rng);
  return x;
}

// The sample autocorrelation of a regular series at lag k: mean product of the lag-k pairs over
// the variance, each about the series mean.
double textbook_acf(const std::vector<double>& x, std::size_t k) {
  double mean = 0;
  for (double v : x) mean += v;
  mean /= static_cast<double>(x.size());
  double var = 0, prod = 0;
  for (double v : x) var += (v - mean) * (v - mean);
  for (std::size_t i = 0; i + k < x.size(); ++i) prod += (x[i] - mean) * (x[i + k] - mean);
  return prod / static_cast<double>(x.size() - k) / (var / static_cast<double>(x.size()));
}

TEST(CorrectionAutocorrelation, Ar1SeriesGivesPhiToTheLag) {
  const double phi = 0.8;
  const std::size_t n = 200000;
  const std::vector<double> x = ar1(phi, n, 11);
  std::vector<double> t(n);
  for (std::size_t k = 0; k < n; ++k) t[k] = 0.5 * static_cast<double>(k);  // 0.5 s epochs
  const std::vector<AutocorrelationBin> bins = empirical_autocorrelation(t, {x}, 0.5, 5.0);
  ASSERT_EQ(bins.size(), 10u);  // bin 0 (lags below 0.25 s) has no pair
  for (std::size_t b = 0; b < bins.size(); ++b) {
    const std::size_t lag = b + 1;
    EXPECT_NEAR(bins[b].lag_s, 0.5 * static_cast<double>(lag), 1e-9);
    EXPECT_EQ(bins[b].pairs, static_cast<long>(n - lag));
    EXPECT_NEAR(bins[b].rho, textbook_acf(x, lag), 1e-9) << lag;
    // Sampling sd of an AR(1) autocorrelation ≈ √((1 + φ²)/(1 − φ²)/n) = 0.005: 4 sd.
    EXPECT_NEAR(bins[b].rho, std::pow(phi, static_cast<double>(lag)), 0.02) << lag;
  }
}

TEST(CorrectionAutocorrelation, PooledSeriesAndGapsAsDocumented) {
  // Two independent AR(1) series of φ 0.6 pooled (as E and N): still φ^lag.
  const std::size_t n = 100000;
  const std::vector<double> a = ar1(0.6, n, 3), b = ar1(0.6, n, 4);
  std::vector<double> t(n);
  for (std::size_t k = 0; k < n; ++k) t[k] = static_cast<double>(k) + (k >= n / 2 ? 1000.0 : 0.0);
  const std::vector<AutocorrelationBin> bins = empirical_autocorrelation(t, {a, b}, 1.0, 3.0);
  ASSERT_EQ(bins.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    // The gap of 1000 s is never bridged: each half of each series gives n/2 − lag pairs per lag.
    EXPECT_EQ(bins[k].pairs, 2 * 2 * static_cast<long>(n / 2 - (k + 1)));
    EXPECT_NEAR(bins[k].rho, std::pow(0.6, static_cast<double>(k + 1)), 0.02) << k;
  }
  // A hand-worked series: +1, −1, +1, −1 at 0, 1, 2, 3 s (mean 0, variance 1): lag 1 every product
  // −1, lag 2 +1, lag 3 −1; the NaN at 4 s is skipped.
  const std::vector<AutocorrelationBin> h =
      empirical_autocorrelation({0, 1, 2, 3, 4}, {{1, -1, 1, -1, std::nan("")}}, 1.0, 3.0);
  ASSERT_EQ(h.size(), 3u);
  EXPECT_DOUBLE_EQ(h[0].rho, -1);
  EXPECT_DOUBLE_EQ(h[1].rho, 1);
  EXPECT_DOUBLE_EQ(h[2].rho, -1);
  EXPECT_EQ(h[0].pairs, 3);
  EXPECT_EQ(h[2].pairs, 1);
  EXPECT_TRUE(empirical_autocorrelation({0, 1}, {{2, 2}}, 1.0, 3.0).empty());  // no variance
}

TEST(CorrectionAutocorrelation, IrregularGaussMarkovPlusWhiteFollowsTheModel) {
  // Epochs 0.1–0.3 s apart, g exactly discretised (ppk_error_model.hpp), w white: the correction's
  // autocorrelation is the model's σ_g²·exp(−lag/τ)/(σ_w² + σ_g²).
  const double sg = 0.008, sw = 0.004, tau = 5;
  std::mt19937_64 rng(9);
  std::normal_distribution<double> z;
  std::uniform_real_distribution<double> step(0.1, 0.3);
  std::vector<double> t{0}, x;
  double g = sg * z(rng);
  x.push_back(g + sw * z(rng));
  while (t.size() < 300000) {
    const double dt = step(rng), phi = std::exp(-dt / tau);
    t.push_back(t.back() + dt);
    g = phi * g + sg * std::sqrt(1 - phi * phi) * z(rng);
    x.push_back(g + sw * z(rng));
  }
  PpkErrorModel m;
  m.gm_sd_h_m = m.gm_sd_v_m = sg;
  m.tau_h_s = m.tau_v_s = tau;
  const AutocorrelationLags lags = autocorrelation_lags(m, t);
  EXPECT_DOUBLE_EQ(lags.max_lag_s, 15);  // 3τ
  EXPECT_DOUBLE_EQ(lags.bin_s, 0.375);   // a fortieth of it, above the 0.2 s median step
  const std::vector<AutocorrelationBin> bins = empirical_autocorrelation(t, {x}, lags.bin_s, lags.max_lag_s);
  ASSERT_GE(bins.size(), 30u);
  for (const AutocorrelationBin& b : bins) {
    const double expected = sg * sg * std::exp(-b.lag_s / tau) / (sw * sw + sg * sg);
    EXPECT_NEAR(model_autocorrelation(sg, tau, sw, b.lag_s), expected, 1e-12);
    // 300000 epochs over ≈ 60000 s ≈ 6000 looks of 2τ: sd of the estimate ≈ 0.02.
    EXPECT_NEAR(b.rho, expected, 0.06) << b.lag_s;
  }
  // The nugget at lag → 0: the GM part's share 0.8.
  EXPECT_NEAR(model_autocorrelation(sg, tau, sw, 0), 0.8, 1e-12);
  EXPECT_EQ(model_autocorrelation(0, tau, sw, 1), 0);  // white
  // A white model: 30 s; a long τ is capped at 120 s.
  EXPECT_DOUBLE_EQ(autocorrelation_lags(PpkErrorModel{}, {0, 1, 2}).max_lag_s, 30);
  EXPECT_DOUBLE_EQ(autocorrelation_lags(PpkErrorModel{}, {0, 1, 2}).bin_s, 1);  // the median step
  m.tau_v_s = 100;
  EXPECT_DOUBLE_EQ(autocorrelation_lags(m, t).max_lag_s, 120);
}

}  // namespace
}  // namespace rangecal
