// config/number_format.hpp: every number the project writes goes through {fmt}; the bytes must be
// the ones printf writes (the outputs were printf's before, and docs/outputs.md documents the
// "%.4f"-style columns). Compared here with the C library's snprintf — an independent
// implementation — over edge cases and 100,000 random doubles, for every conversion the code uses.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "config/number_format.hpp"

namespace rangecal {
namespace {

std::string c_printf(const char* format, double v) {
  char buf[512];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::vector<double> test_values() {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> v = {0.0,
                           -0.0,
                           0.5,
                           1.5,
                           2.5,
                           -0.5,
                           -2.5,
                           0.125,
                           0.0625,
                           1e-5,
                           1e-4,
                           0.00005,
                           0.00015,
                           2.675,
                           1.005,
                           9.9995,
                           99999.95,
                           123456.5,
                           1e15,
                           1e16,
                           1e17,
                           1e21,
                           1e22,
                           1e300,
                           -1e300,
                           5e-324,
                           2.2250738585072014e-308,
                           1.7976931348623157e308,
                           0.3,
                           0.1,
                           1.0 / 3.0,
                           -0.00004,
                           -0.00005,
                           4503599627370495.5,
                           9007199254740993.0,
                           inf,
                           -inf,
                           nan,
                           -nan};
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> wide(-1e6, 1e6);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int i = 0; i < 20000; ++i) {
    const std::uint64_t bits = rng();
    double x;
    std::memcpy(&x, &bits, sizeof x);
    if (std::isfinite(x) && std::abs(x) < 1e200) v.push_back(x);  // %f of 1e300 is 300 digits: fine, but slow
    v.push_back(wide(rng));
    v.push_back(unit(rng) * 1e-3);
    // Exact ties at the printed digit (x.xxx5 in binary), where rounding rules differ most.
    v.push_back(std::ldexp(static_cast<double>(rng() % 1000000), -static_cast<int>(rng() % 24)));
    v.push_back(std::round(wide(rng)) + 0.5);
  }
  return v;
}

// Every printf conversion the project passes to format_number (grep format_number), plus the widths
// of the fixed-width writers.
const char* const kConversions[] = {
    "%.0f",  "%.1f",  "%.2f",   "%.3f",   "%.4f",   "%.6f",   "%.9f",  "%g",    "%.3g",   "%.4g",
    "%.6g",  "%.9g",  "%.10g",  "%.15g",  "%.17g",  "%.2e",   "%+.2f", "%+.0f", "%02.0f", "%8.0f",
    "%9.0f", "%8.3f", "%16.3f", "%14.9f", "%13.9f", "%10.4f", "%8.4f", "%6.2f", "%6.1f",  "%8.1f"};

TEST(NumberFormat, FormatNumberIsPrintfForEveryConversion) {
  const std::vector<double> values = test_values();
  for (const char* conv : kConversions) {
    int differing = 0;
    for (double x : values) {
      const std::string want = c_printf(conv, x);
      const std::string got = format_number(conv, x);
      if (got != want && ++differing <= 5)
        ADD_FAILURE() << conv << " of " << x << ": '" << got << "' vs '" << want << "'";
    }
    EXPECT_EQ(differing, 0) << conv;
  }
}

// The writers call fmt::format directly with "{:…}" specs; each must give printf's bytes. A width
// on a float needs '>' (fmt 9 left-aligns nan/inf), which the last case shows.
TEST(NumberFormat, FmtSpecsTheWritersUseArePrintf) {
  struct Pair {
    const char* printf_spec;
    std::string (*fmt)(double);
  };
  const Pair pairs[] = {
      {"%.1f", [](double x) { return fmt::format("{:.1f}", x); }},
      {"%.2f", [](double x) { return fmt::format("{:.2f}", x); }},
      {"%.4f", [](double x) { return fmt::format("{:.4f}", x); }},
      {"%.6f", [](double x) { return fmt::format("{:.6f}", x); }},
      {"%.9f", [](double x) { return fmt::format("{:.9f}", x); }},
      {"%.3g", [](double x) { return fmt::format("{:.3g}", x); }},
      {"%.6g", [](double x) { return fmt::format("{:.6g}", x); }},
      {"%.9g", [](double x) { return fmt::format("{:.9g}", x); }},
      {"%.10g", [](double x) { return fmt::format("{:.10g}", x); }},
      {"%.17g", [](double x) { return fmt::format("{:.17g}", x); }},
      {"%+.0f", [](double x) { return fmt::format("{:+.0f}", x); }},
      {"%+.2f", [](double x) { return fmt::format("{:+.2f}", x); }},
      {"%8.1f", [](double x) { return fmt::format("{:>8.1f}", x); }},
      {"%8.3f", [](double x) { return fmt::format("{:>8.3f}", x); }},
      {"%16.3f", [](double x) { return fmt::format("{:>16.3f}", x); }},
      {"%14.9f", [](double x) { return fmt::format("{:>14.9f}", x); }},
      {"%13.9f", [](double x) { return fmt::format("{:>13.9f}", x); }},
      {"%10.4f", [](double x) { return fmt::format("{:>10.4f}", x); }},
      {"%8.4f", [](double x) { return fmt::format("{:>8.4f}", x); }},
      {"%6.2f", [](double x) { return fmt::format("{:>6.2f}", x); }},
      {"%6.1f", [](double x) { return fmt::format("{:>6.1f}", x); }},
  };
  const std::vector<double> values = test_values();
  for (const Pair& p : pairs) {
    int differing = 0;
    for (double x : values) {
      const std::string want = c_printf(p.printf_spec, x);
      const std::string got = p.fmt(x);
      if (got != want && ++differing <= 5)
        ADD_FAILURE() << p.printf_spec << " of " << x << ": '" << got << "' vs '" << want << "'";
    }
    EXPECT_EQ(differing, 0) << p.printf_spec;
  }
  // Without '>', fmt 9 pads a non-finite value on the right: the reason the writers spell it out.
  EXPECT_EQ(fmt::format("{:8.3f}", std::numeric_limits<double>::infinity()), "inf     ");
  EXPECT_EQ(c_printf("%8.3f", std::numeric_limits<double>::infinity()), "     inf");
}

TEST(NumberFormat, IntegersStringsAndHex) {
  char buf[128];
  for (long long v : {0LL, 7LL, -7LL, 123456LL, -2026LL, 9LL}) {
    std::snprintf(buf, sizeof buf, "%04lld|%3lld|%-3lld|%02llx|%02llX", v, v, v, v & 0xff, v & 0xff);
    EXPECT_EQ(fmt::format("{:04}|{:3}|{:<3}|{:02x}|{:02X}", v, v, v, v & 0xff, v & 0xff), buf);
  }
  for (int nd = 1; nd <= 9; ++nd) {
    std::snprintf(buf, sizeof buf, ".%0*lld", nd, 42LL);
    EXPECT_EQ(fmt::format(".{:0{}}", 42LL, nd), buf);
  }
  std::snprintf(buf, sizeof buf, "  %-5s %16s|", "ab", "right");
  EXPECT_EQ(fmt::format("  {:<5} {:>16}|", "ab", "right"), buf);
}

TEST(NumberFormat, FormatFiniteBlanksNonFinite) {
  EXPECT_EQ(format_finite("%.3f", 1.25), "1.250");
  EXPECT_EQ(format_finite("%.3f", std::numeric_limits<double>::quiet_NaN()), "");
  EXPECT_EQ(format_finite("%.3f", -std::numeric_limits<double>::infinity()), "");
}

}  // namespace
}  // namespace rangecal
