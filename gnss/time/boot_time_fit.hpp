#pragma once
// Boot time → UTC for autopilot logs. A flight controller stamps every logged message with its
// own clock, microseconds since boot; its GNSS messages carry, beside that stamp, the receiver's
// time of the fix (PX4 `time_utc_usec`; ArduPilot GPS week and milliseconds of week). Pairs
// (boot µs, UTC) give the mapping
//
//   utc(t) = t + offset + drift · (t − t_ref)        (t in boot µs; offset at t_ref)
//
// with `drift` the boot clock's rate error. The pairs are noisy: the boot stamp is the time the
// autopilot *read* the GNSS message, so it lags the fix by the receiver's output latency plus a
// few ms of serial-link and scheduling jitter (±5 ms, one stamp 13 ms off, in the real PX4 sample
// `sample_log_small.ulg`). The constant part of that lag cannot be told from the offset by the
// pairs themselves, so it is given (BootTimeFitOptions::gnss_lag_us, docs/gnss.md "Receiver lag":
// 110–220 ms for the receivers autopilots carry, not a few ms) and each boot stamp is moved back
// by it before the fit; only the jitter shows in the residuals.
//
// The fit (fit_boot_time):
//  1. A robust first model: offset only, the median of UTC − boot; with the drift term, Tukey's
//     resistant line (medians of the first and last thirds give the slope; the median residual
//     the offset). Either ignores up to a third of wild pairs.
//  2. Rejection of jumps: a pair whose residual exceeds min(cap, max(floor, k·σ)) is rejected, σ
//     being the MAD-based standard deviation 1.4826·median|residual|. Floor 5 ms, k = 5, cap
//     100 ms by default: the arrival jitter above (σ ≈ 3 ms) passes, a GNSS time that jumps (a
//     second's step, a week roll, a receiver reporting before its clock is set) does not. A fixed
//     1 ms threshold would reject most of the real sample's honest pairs; the cap keeps a log whose
//     pairs mostly disagree (σ itself made of jumps) from accepting them all.
//  3. Least squares on the kept pairs; residuals of all pairs recomputed from it and the rejection
//     repeated once with the same threshold; least squares again on the final set.
//  The drift term is fitted only when the kept pairs span more than 60 s and number at least 10:
//  a crystal's 20–50 ppm move the offset by 1–3 ms a minute, at the level of the jitter, so a
//  shorter span cannot separate the drift from noise and the offset alone is the better model.
//  Fewer than 3 pairs, or fewer kept than half of them, is an error: the GNSS time then does not
//  determine the mapping.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

/// One GNSS message: the autopilot's boot-time stamp and the receiver's UTC of the fix.
struct BootUtcPair {
  std::int64_t boot_us = 0;  ///< µs since the autopilot booted
  UtcTime utc;
};

struct BootTimeFitOptions {
  double drift_min_span_s = 60;      ///< fit a drift only when the kept pairs span more than this (s)
  std::size_t drift_min_pairs = 10;  ///< … and number at least this many
  double reject_floor_us = 5000;     ///< residual always accepted up to this (µs)
  double reject_sigmas = 5;          ///< … and up to this many MAD-based σ
  double reject_cap_us = 100000;     ///< … but never beyond this (µs)
  /// The receiver's output latency (µs): a GNSS message is stamped when it reaches the autopilot,
  /// this long after the instant its UTC names, so the pair's boot time is its stamp minus this.
  std::int64_t gnss_lag_us = 0;
};

/// The fitted mapping and how well the pairs agree with it.
struct BootTimeFit {
  std::int64_t ref_boot_us = 0;  ///< t_ref: boot time of the middle pair
  std::int64_t offset_ns = 0;    ///< UTC − boot time at t_ref (ns since 1970 minus boot ns)
  double drift_ppm = 0;          ///< boot clock rate error: UTC advances (1 + drift·1e-6) s per boot s
  bool drift_fitted = false;
  std::size_t pairs = 0;     ///< pairs given
  std::size_t used = 0;      ///< pairs kept
  std::size_t rejected = 0;  ///< pairs rejected as jumps
  double reject_threshold_us = 0;
  double residual_rms_us = 0;                        ///< of the kept pairs
  double residual_max_us = 0;                        ///< largest |residual| of the kept pairs
  std::int64_t first_boot_us = 0, last_boot_us = 0;  ///< span of the kept pairs (stamps − lag)
  std::int64_t gnss_lag_us = 0;                      ///< the lag the stamps were moved back by (µs)

  /// UTC of a boot-time stamp (rounded to the ns).
  UtcTime to_utc(std::int64_t boot_us) const;
};

/// Fits the mapping as described at the top of this file. Pairs may come in any order. Throws
/// rangecal::Error (input) on `file` (line 0, field `field`) when fewer than 3 pairs are given or
/// when fewer than half of them agree with the fit, stating the counts.
BootTimeFit fit_boot_time(std::vector<BootUtcPair> pairs, const std::string& file, const std::string& field,
                          const BootTimeFitOptions& options = {});

}  // namespace rangecal
