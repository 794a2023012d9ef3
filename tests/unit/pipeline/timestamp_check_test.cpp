// Whole-second / leap-second errors in frame time stamps ("a 1 s or 18 s offset is
// reported as a timestamp error"). Truth from the simulator: the demo scenario's true lamp track
// and the true lamp pixels of camera 1 at the frames' true instants; the stamps are then shifted.
#include "pipeline/steps/timestamp_check.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "pipeline/demo/demo_scenario_text.hpp"
#include "pipeline/simulate/mission_simulator.hpp"
#include "pipeline/simulate/scenario.hpp"

namespace rangecal {
namespace {

struct Scene {
  LampTrack track;
  std::vector<std::pair<UtcTime, Eigen::Vector2d>> true_pixels;  // true instant, true pixel
};

const Scene& scene() {
  static const Scene s = [] {
    Scene sc;
    const SimMission m = simulate_mission(parse_scenario(demo_scenario_json(), "demo"));
    for (const SimEpoch& e : m.epochs) {
      LampEpoch l;
      l.utc = e.utc;
      l.enu = e.lamp_true;
      l.sd_enu = Eigen::Vector3d::Constant(0.01);
      sc.track.epochs.push_back(l);
    }
    for (const SimFrame& f : m.cameras[0].frames)
      if (f.in_view) sc.true_pixels.emplace_back(f.true_utc, f.lamp_px);
    return sc;
  }();
  return s;
}

TimestampOffsetCheck check_with_stamp_error(double error_s) {
  const Scene& s = scene();
  const HermiteTrack track(s.track, 1.0);
  std::vector<std::pair<UtcTime, Eigen::Vector2d>> stamped;
  // A frame is only paired when its stamp falls on the track (as the align stage does).
  for (const auto& [t, uv] : s.true_pixels) {
    const UtcTime stamp{t.ns + static_cast<std::int64_t>(std::llround(error_s * 1e9))};
    if (track.sample(stamp).status == TrackSampleStatus::ok) stamped.emplace_back(stamp, uv);
  }
  const TimestampOffsetCheck r = check_timestamp_offset(stamped, track);
  std::printf("stamp error %+g s: %d pairs, rms %.2f px as stamped, best %+g s with %.2f px\n", error_s,
              r.n_points, r.rms_at_zero_px, r.best_offset_s, r.rms_at_best_px);
  return r;
}

TEST(TimestampCheck, CorrectStampsAreNotFlagged) {
  const TimestampOffsetCheck r = check_with_stamp_error(0.0);
  EXPECT_GE(r.n_points, 50);
  EXPECT_FALSE(r.offset_detected);
  EXPECT_EQ(r.best_offset_s, 0.0);
  // True pixels and positions: only the lens' k1 (unmodelled by the DLT) is left.
  EXPECT_LT(r.rms_at_zero_px, 3.0);
}

TEST(TimestampCheck, OneSecondLateIsFound) {
  const TimestampOffsetCheck r = check_with_stamp_error(1.0);
  EXPECT_TRUE(r.offset_detected);
  EXPECT_EQ(r.best_offset_s, -1.0);
  EXPECT_LT(r.rms_at_best_px, 3.0);
  EXPECT_GT(r.rms_at_zero_px, 100.0);
}

TEST(TimestampCheck, OneSecondEarlyIsFound) {
  const TimestampOffsetCheck r = check_with_stamp_error(-1.0);
  EXPECT_TRUE(r.offset_detected);
  EXPECT_EQ(r.best_offset_s, 1.0);
}

TEST(TimestampCheck, GpstWrittenAsUtcIsFound) {
  // Stamps 18 s late: GPST − UTC since 2017.
  const TimestampOffsetCheck r = check_with_stamp_error(18.0);
  EXPECT_TRUE(r.offset_detected);
  EXPECT_EQ(r.best_offset_s, -18.0);
  EXPECT_LT(r.rms_at_best_px, 6.0);  // ~30 pairs from the first 12 s of flight still overlap
}

TEST(TimestampCheck, TooFewPairsDetectNothing) {
  const Scene& s = scene();
  const HermiteTrack track(s.track, 1.0);
  std::vector<std::pair<UtcTime, Eigen::Vector2d>> few(s.true_pixels.begin(), s.true_pixels.begin() + 8);
  const TimestampOffsetCheck r = check_timestamp_offset(few, track);
  EXPECT_FALSE(r.offset_detected);
  EXPECT_LT(r.n_points, 12);
}

}  // namespace
}  // namespace rangecal
