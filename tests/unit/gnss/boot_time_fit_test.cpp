// Boot time → UTC fit: offset only for short logs, drift for long ones, jump rejection with the
// MAD-based threshold, and the errors when the GNSS time cannot determine the mapping.
#include "gnss/time/boot_time_fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "config/error.hpp"

namespace rangecal {
namespace {

// Boot 0 is this UTC instant in the synthetic logs.
const UtcTime kBootZero = utc_from_civil(2021, 4, 21, 6, 30, 38, 140'534'000);

// UTC of boot time t (µs) for a clock with `ppm` rate error, plus `noise_us`.
UtcTime truth(std::int64_t t_us, double ppm, double noise_us = 0) {
  return UtcTime{kBootZero.ns + t_us * 1000 + std::llround(t_us * 1000.0 * ppm * 1e-6 + noise_us * 1e3)};
}

TEST(BootTimeFit, ShortLogFitsTheOffsetOnlyAndKeepsArrivalJitter) {
  std::mt19937 rng(7);
  std::normal_distribution<double> jitter(0, 3000);  // 3 ms, as in the real PX4 sample
  std::vector<BootUtcPair> pairs;
  double mean = 0;
  for (int i = 0; i < 50; ++i) {
    const std::int64_t t = 20'000'000 + i * 200'000;  // 5 Hz for 10 s
    const double n = jitter(rng);
    mean += n / 50;
    pairs.push_back({t, truth(t, 0, n)});
  }
  const BootTimeFit f = fit_boot_time(pairs, "log", "gps");
  EXPECT_FALSE(f.drift_fitted);
  EXPECT_EQ(f.used, 50u);
  EXPECT_EQ(f.rejected, 0u);
  EXPECT_GE(f.reject_threshold_us, 5000.0);
  // The offset is the mean of the pairs' offsets.
  EXPECT_NEAR(static_cast<double>(f.to_utc(25'000'000).ns - truth(25'000'000, 0).ns), mean * 1e3, 1.0);
  EXPECT_GT(f.residual_rms_us, 1500);
  EXPECT_LT(f.residual_rms_us, 4500);
  EXPECT_GE(f.residual_max_us, f.residual_rms_us);
}

TEST(BootTimeFit, JumpsAreRejectedAndCounted) {
  std::vector<BootUtcPair> pairs;
  for (int i = 0; i < 40; ++i) {
    const std::int64_t t = 10'000'000 + i * 250'000;
    pairs.push_back({t, truth(t, 0, (i % 2 ? 400 : -400))});
  }
  pairs[5].utc.ns += kNsPerSecond;        // a second's step
  pairs[17].utc.ns -= 18 * kNsPerSecond;  // GPST taken for UTC
  pairs[30].utc.ns += 30'000'000;         // 30 ms late
  const BootTimeFit f = fit_boot_time(pairs, "log", "gps");
  EXPECT_EQ(f.rejected, 3u);
  EXPECT_EQ(f.used, 37u);
  EXPECT_EQ(f.reject_threshold_us, 5000.0);  // σ_MAD ≈ 0.6 ms: the floor applies
  // Kept: 18 pairs at +400 µs, 19 at −400 µs; the offset is their mean.
  EXPECT_NEAR(static_cast<double>(f.to_utc(12'000'000).ns - truth(12'000'000, 0).ns), -400e3 / 37, 1);
  EXPECT_NEAR(f.residual_max_us, 400 + 400.0 / 37, 1e-3);
}

TEST(BootTimeFit, LongLogFitsTheDrift) {
  std::vector<BootUtcPair> pairs;
  // 300 s at 5 Hz, boot clock 30 ppm slow, 1 ms jitter and two jumps; given in reverse order.
  std::mt19937 rng(3);
  std::normal_distribution<double> jitter(0, 1000);
  for (int i = 0; i < 1500; ++i) {
    const std::int64_t t = 60'000'000 + i * 200'000;
    pairs.push_back({t, truth(t, 30, jitter(rng))});
  }
  pairs[100].utc.ns += kNsPerSecond;
  pairs[1400].utc.ns -= kNsPerSecond;
  std::reverse(pairs.begin(), pairs.end());
  const BootTimeFit f = fit_boot_time(pairs, "log", "gps");
  EXPECT_TRUE(f.drift_fitted);
  EXPECT_NEAR(f.drift_ppm, 30, 0.2);
  EXPECT_EQ(f.rejected, 2u);
  EXPECT_NEAR(f.residual_rms_us, 1000, 100);
  EXPECT_EQ(f.first_boot_us, 60'000'000);
  EXPECT_EQ(f.last_boot_us, 60'000'000 + 1499 * 200'000);
  for (std::int64_t t : {60'000'000LL, 200'000'000LL, 359'800'000LL})
    EXPECT_NEAR(static_cast<double>(f.to_utc(t).ns - truth(t, 30).ns), 0, 150'000) << t;  // < 0.15 ms
  // The same pairs cut to 50 s: offset only (the drift moves the offset by 1.5 ms, within noise).
  std::vector<BootUtcPair> shorter(pairs.end() - 250, pairs.end());
  EXPECT_FALSE(fit_boot_time(shorter, "log", "gps").drift_fitted);
}

TEST(BootTimeFit, ExactPairsGiveTheExactMapping) {
  std::vector<BootUtcPair> pairs;
  for (int i = 0; i < 10; ++i) pairs.push_back({i * 1'000'000LL, truth(i * 1'000'000LL, 0)});
  const BootTimeFit f = fit_boot_time(pairs, "log", "gps");
  EXPECT_EQ(f.to_utc(0), kBootZero);
  EXPECT_EQ(f.to_utc(123'456'789), truth(123'456'789, 0));
  EXPECT_EQ(f.residual_rms_us, 0);
}

void expect_fit_error(const std::vector<BootUtcPair>& pairs, const std::string& needle) {
  try {
    fit_boot_time(pairs, "flight.ulg", "D sensor_gps.time_utc_usec");
    ADD_FAILURE() << needle;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "flight.ulg");
    EXPECT_EQ(e.field(), "D sensor_gps.time_utc_usec");
    EXPECT_NE(e.reason().find(needle), std::string::npos) << e.what();
  }
}

TEST(BootTimeFit, TooFewOrDisagreeingPairsAreInputErrors) {
  expect_fit_error({}, "no usable GNSS time");
  expect_fit_error({{0, truth(0, 0)}, {1000, truth(1000, 0)}}, "2 message(s)");
  // Three pairs, each a second apart from the others: no majority (σ_MAD = 1.5 s, the 100 ms cap
  // applies).
  expect_fit_error({{0, truth(0, 0)},
                    {1000, UtcTime{truth(1000, 0).ns + kNsPerSecond}},
                    {2000, UtcTime{truth(2000, 0).ns + 2 * kNsPerSecond}}},
                   "only 1 of 3");
  expect_fit_error({{0, truth(0, 0)}, {1, truth(1, 0)}, {std::int64_t{1} << 62, truth(2, 0)}}, "plausible");
}

}  // namespace
}  // namespace rangecal
