#pragma once
// Whole-second and leap-second errors in a camera's frame time stamps.
//
// Frames are paired with the lamp track by UTC (seed 002 §2.2). A frame clock that is off by a
// whole number of seconds — GPST written as UTC (18 s since 2017), a missed PPS edge (1 s) —
// pairs every pixel with where the lamp was δ earlier or later; at 2–10 m/s that is metres, and
// no camera model can explain the pairs. The check samples the track at (stamp + δ) for a few
// candidate offsets and fits one pinhole camera (linear DLT, seed 000 eqs. 1–3) to each set of
// pairs: if a non-zero δ explains the pairs far better than δ = 0, the stamps are off by −δ.
#include <Eigen/Core>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "gnss/time/utc_time.hpp"
#include "gnss/track/hermite_interpolation.hpp"

namespace rangecal {

struct TimestampOffsetCheck {
  double best_offset_s = 0;  ///< δ (s) whose pairs a pinhole camera fits best (0 = stamps agree)
  double rms_at_zero_px = std::numeric_limits<double>::quiet_NaN();  ///< DLT rms with the stamps as given
  double rms_at_best_px = std::numeric_limits<double>::quiet_NaN();  ///< DLT rms at best_offset_s
  int n_points = 0;                                                  ///< pairs used at δ = 0
  bool offset_detected = false;  ///< best_offset_s ≠ 0 and it fits ≥ 1.5× and 2 px better than δ = 0
};

/// The candidate offsets tried by default (s): ±1, ±2 (clock slips) and ±17, ±18, ±19 (GPST−UTC
/// leap seconds of recent years).
const std::vector<double>& default_timestamp_offsets_s();

/// Runs the check on (frame UTC, lamp pixel) pairs. Needs ≥ 12 pairs whose shifted instants fall
/// on the track; otherwise returns n_points < 12 and nothing detected. Never throws for bad
/// geometry (a candidate whose DLT fails is skipped).
TimestampOffsetCheck check_timestamp_offset(
    const std::vector<std::pair<UtcTime, Eigen::Vector2d>>& pixels, const HermiteTrack& track,
    const std::vector<double>& candidates_s = default_timestamp_offsets_s());

/// The warning for a detected offset: by how much the stamps look off, both rms figures, and the
/// likely cause (±18 s ± 1: a GPST/UTC leap-second mix-up; otherwise a whole-second clock error).
std::string describe_timestamp_offset(const TimestampOffsetCheck& check);

}  // namespace rangecal
