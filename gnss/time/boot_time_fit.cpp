#include "gnss/time/boot_time_fit.hpp"

#include <algorithm>
#include <cmath>

#include "config/error.hpp"

namespace rangecal {
namespace {

// Bounds that keep every product below in int64: 4e15 µs is 127 years of boot time (PX4's SITL
// stamps boot time as Unix µs, 1.7e15 in 2024); 4e18 ns of UTC is the year 2096.
constexpr std::int64_t kMaxAbsBootUs = 4'000'000'000'000'000;
/// The largest receiver lag taken (µs): receivers answer within a few hundred ms; a second is a unit mistake.
constexpr std::int64_t kMaxGnssLagUs = 1'000'000;
constexpr std::int64_t kMaxAbsUtcNs = 4'000'000'000'000'000'000;
// Normal-distribution scale of the median absolute deviation (σ = 1.4826·MAD).
constexpr double kMadToSigma = 1.4826;

double median(std::vector<double> v) {
  const std::size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(h), v.end());
  const double hi = v[h];
  if (v.size() % 2) return hi;
  return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(h)));
}

struct Line {
  double a = 0;  // ns at x = 0
  double b = 0;  // ns per s
  double at(double x) const { return a + b * x; }
};

// Least squares over the kept points; the slope only when `drift`.
Line least_squares(const std::vector<double>& x, const std::vector<double>& y, const std::vector<bool>& keep,
                   bool drift) {
  double n = 0, sx = 0, sy = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (keep[i]) n += 1, sx += x[i], sy += y[i];
  Line l;
  if (n == 0) return l;
  const double mx = sx / n, my = sy / n;
  l.a = my;
  if (!drift) return l;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (keep[i]) sxx += (x[i] - mx) * (x[i] - mx), sxy += (x[i] - mx) * (y[i] - my);
  if (sxx > 0) l.b = sxy / sxx;
  l.a = my - l.b * mx;
  return l;
}

// Tukey's resistant line: slope through the medians of the first and last thirds (x sorted).
Line resistant_line(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size(), t = n / 3;
  const std::vector<double> xf(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(t)),
      yf(y.begin(), y.begin() + static_cast<std::ptrdiff_t>(t)),
      xl(x.end() - static_cast<std::ptrdiff_t>(t), x.end()),
      yl(y.end() - static_cast<std::ptrdiff_t>(t), y.end());
  Line l;
  const double dx = median(xl) - median(xf);
  if (dx > 0) l.b = (median(yl) - median(yf)) / dx;
  std::vector<double> r(n);
  for (std::size_t i = 0; i < n; ++i) r[i] = y[i] - l.b * x[i];
  l.a = median(r);
  return l;
}

}  // namespace

UtcTime BootTimeFit::to_utc(std::int64_t boot_us) const {
  const double dt_ns = static_cast<double>(boot_us - ref_boot_us) * 1e3;
  return UtcTime{boot_us * 1000 + offset_ns + std::llround(drift_ppm * 1e-6 * dt_ns)};
}

BootTimeFit fit_boot_time(std::vector<BootUtcPair> pairs, const std::string& file, const std::string& field,
                          const BootTimeFitOptions& o) {
  BootTimeFit f;
  f.pairs = pairs.size();
  if (pairs.size() < 3)
    throw_input_error(file, 0, field,
                      "no usable GNSS time to map boot time to UTC: " + std::to_string(pairs.size()) +
                          " message(s) with a 3-D fix and a time, at least 3 are needed");
  for (const BootUtcPair& p : pairs)
    if (p.boot_us < -kMaxAbsBootUs || p.boot_us > kMaxAbsBootUs || p.utc.ns < -kMaxAbsUtcNs ||
        p.utc.ns > kMaxAbsUtcNs)
      throw_input_error(file, 0, field,
                        "a GNSS message's boot time (" + std::to_string(p.boot_us) + " µs) or UTC (" +
                            std::to_string(p.utc.ns) + " ns) is outside any plausible range");
  if (o.gnss_lag_us < 0 || o.gnss_lag_us > kMaxGnssLagUs)
    throw_input_error(file, 0, field,
                      "a GNSS receiver lag of " + std::to_string(o.gnss_lag_us) + " µs is outside [0, 1 s]");
  f.gnss_lag_us = o.gnss_lag_us;
  for (BootUtcPair& p : pairs) p.boot_us -= o.gnss_lag_us;  // the boot time of the fix itself
  std::stable_sort(pairs.begin(), pairs.end(),
                   [](const BootUtcPair& a, const BootUtcPair& b) { return a.boot_us < b.boot_us; });
  const std::size_t n = pairs.size();
  f.ref_boot_us = pairs[n / 2].boot_us;
  // Offsets d = UTC − boot in integer ns, relative to their median so that the doubles below hold
  // ns-exact small numbers.
  std::vector<std::int64_t> d(n);
  std::vector<double> dd(n);
  for (std::size_t i = 0; i < n; ++i) {
    d[i] = pairs[i].utc.ns - pairs[i].boot_us * 1000;
    dd[i] = static_cast<double>(d[i]);
  }
  const auto d_ref = static_cast<std::int64_t>(median(dd));
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = static_cast<double>(pairs[i].boot_us - f.ref_boot_us) * 1e-6;
    y[i] = static_cast<double>(d[i] - d_ref);
  }
  const auto drift_for = [&](const std::vector<bool>& keep) {
    std::size_t count = 0, first = n, last = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (keep[i]) ++count, first = std::min(first, i), last = i;
    return count >= o.drift_min_pairs && count > 0 &&
           static_cast<double>(pairs[last].boot_us - pairs[first].boot_us) * 1e-6 > o.drift_min_span_s;
  };
  std::vector<bool> keep(n, true);
  bool drift = drift_for(keep);
  Line line;
  if (drift) {
    line = resistant_line(x, y);
  } else {
    line.a = median(y);
  }
  std::vector<double> abs_r(n);
  for (std::size_t i = 0; i < n; ++i) abs_r[i] = std::abs(y[i] - line.at(x[i]));
  const double thr_ns =
      std::min(o.reject_cap_us * 1e3,
               std::max(o.reject_floor_us * 1e3, o.reject_sigmas * kMadToSigma * median(abs_r)));
  f.reject_threshold_us = thr_ns * 1e-3;
  const auto classify = [&] {
    for (std::size_t i = 0; i < n; ++i) keep[i] = std::abs(y[i] - line.at(x[i])) <= thr_ns;
  };
  classify();  // against the robust model
  line = least_squares(x, y, keep, drift_for(keep));
  classify();  // once more, against the least-squares fit of the pairs kept
  f.used = static_cast<std::size_t>(std::count(keep.begin(), keep.end(), true));
  f.rejected = n - f.used;
  if (f.used * 2 < n || f.used < 2)
    throw_input_error(file, 0, field,
                      "the GNSS times do not agree on one boot-time offset: only " + std::to_string(f.used) +
                          " of " + std::to_string(n) + " messages lie within " +
                          std::to_string(std::llround(f.reject_threshold_us)) + " µs of the fit");
  drift = drift_for(keep);
  line = least_squares(x, y, keep, drift);
  f.drift_fitted = drift;
  f.offset_ns = d_ref + std::llround(line.a);
  f.drift_ppm = line.b * 1e-3;  // ns per s → µs per s
  double ss = 0;
  bool first = true;
  for (std::size_t i = 0; i < n; ++i) {
    if (!keep[i]) continue;
    const double r = std::abs(y[i] - line.at(x[i])) * 1e-3;
    ss += r * r;
    f.residual_max_us = std::max(f.residual_max_us, r);
    if (first) f.first_boot_us = pairs[i].boot_us, first = false;
    f.last_boot_us = pairs[i].boot_us;
  }
  f.residual_rms_us = std::sqrt(ss / static_cast<double>(f.used));
  return f;
}

}  // namespace rangecal
