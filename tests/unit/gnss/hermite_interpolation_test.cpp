#include "gnss/track/hermite_interpolation.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "config/error.hpp"

namespace rangecal {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Simulated truth: a vertical ascent with a changing acceleration a(t) = a0 + a1·sin(ωt)
// (z = z0 + v0 t + ½ a0 t² + a1 (t/ω − sin(ωt)/ω²)) plus a smooth horizontal wobble.
struct Ascent {
  double z0 = 2.0, v0 = 1.0, a0 = 0.3, a1 = 1.5, w = 2 * kPi / 4.0;
  Eigen::Vector3d pos(double t) const {
    return {0.3 * std::sin(2 * kPi * 0.4 * t + 0.3), 0.2 * std::cos(2 * kPi * 0.25 * t),
            z0 + v0 * t + 0.5 * a0 * t * t + a1 * (t / w - std::sin(w * t) / (w * w))};
  }
  Eigen::Vector3d vel(double t) const {
    return {0.3 * 2 * kPi * 0.4 * std::cos(2 * kPi * 0.4 * t + 0.3),
            -0.2 * 2 * kPi * 0.25 * std::sin(2 * kPi * 0.25 * t),
            v0 + a0 * t + a1 * (1 - std::cos(w * t)) / w};
  }
};

const UtcTime kT0 = utc_from_civil(2026, 5, 10, 3, 0, 0, 100'000'000);

UtcTime at(double t) {
  return add_seconds(kT0, t);
}
double since(UtcTime u) {
  return seconds_between(kT0, u);
}

/// 10 Hz track over [0, duration] s, skipping epochs inside (hole_from, hole_to).
LampTrack make_track(const Ascent& a, double duration, bool with_velocity, double hole_from = -1,
                     double hole_to = -1) {
  LampTrack tr;
  for (int k = 0; k * 0.1 <= duration + 1e-9; ++k) {
    const double t = k * 0.1;
    if (t > hole_from + 1e-9 && t < hole_to - 1e-9) continue;
    LampEpoch e;
    e.utc = at(t);
    e.enu = a.pos(t);
    e.sd_enu = Eigen::Vector3d(0.01, 0.012, 0.02) * (1 + 0.1 * (k % 3));
    e.quality = 1;
    if (with_velocity) e.vel_enu = a.vel(t);
    tr.epochs.push_back(e);
  }
  return tr;
}

double max_error_at_camera_times(const HermiteTrack& ht, const Ascent& a, double from, double to) {
  // A 500 fps camera whose frames are offset 0.37 ms from the GNSS epochs.
  double worst = 0;
  for (double t = from + 0.00037; t < to; t += 0.002) {
    const TrackSample s = ht.sample(at(t));
    EXPECT_EQ(s.status, TrackSampleStatus::ok) << t;
    worst = std::max(worst, (s.enu - a.pos(since(at(t)))).norm());
  }
  return worst;
}

TEST(HermiteInterpolation, AcceleratingAscentWithinOneMillimetreFromPosVelocity) {
  const Ascent a;
  const HermiteTrack ht(make_track(a, 20.0, true), 0.5);
  EXPECT_TRUE(ht.tangent_from_velocity(5));
  EXPECT_LT((ht.tangent(5) - a.vel(0.5)).norm(), 1e-12);
  const double worst = max_error_at_camera_times(ht, a, 0.0, 20.0);
  ::testing::Test::RecordProperty("max_error_m", std::to_string(worst));
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(worst, 1e-4);  // with exact tangents the error is O(h⁴): far below the bar
}

TEST(HermiteInterpolation, AcceleratingAscentWithinOneMillimetreFromFiniteDifferences) {
  const Ascent a;
  const HermiteTrack ht(make_track(a, 20.0, false), 0.5);
  EXPECT_FALSE(ht.tangent_from_velocity(5));
  const double worst = max_error_at_camera_times(ht, a, 0.0, 20.0);
  ::testing::Test::RecordProperty("max_error_m", std::to_string(worst));
  EXPECT_LT(worst, 1e-3);
  // Linear interpolation would be far off on this track: the method matters.
  double worst_linear = 0;
  for (double t = 0.05; t < 19.9; t += 0.1) {
    const Eigen::Vector3d lin = 0.5 * (a.pos(t - 0.05) + a.pos(t + 0.05));
    worst_linear = std::max(worst_linear, (lin - a.pos(t)).norm());
  }
  EXPECT_GT(worst_linear, 2e-3);
}

TEST(HermiteInterpolation, ExactAtEpochsAndSdInterpolatedLinearly) {
  const Ascent a;
  const LampTrack tr = make_track(a, 3.0, false);
  const HermiteTrack ht(tr, 0.5);
  for (const LampEpoch& e : tr.epochs) {
    const TrackSample s = ht.sample(e.utc);
    ASSERT_EQ(s.status, TrackSampleStatus::ok);
    EXPECT_EQ(s.enu, e.enu);
    EXPECT_EQ(s.sd_enu, e.sd_enu);
  }
  const TrackSample s = ht.sample(add_seconds(tr.epochs[4].utc, 0.025));  // a quarter into [4, 5]
  EXPECT_EQ(s.segment, 4u);
  EXPECT_NEAR(s.interval_s, 0.1, 1e-12);
  const Eigen::Vector3d sd = 0.75 * tr.epochs[4].sd_enu + 0.25 * tr.epochs[5].sd_enu;
  EXPECT_LT((s.sd_enu - sd).norm(), 1e-15);
}

TEST(HermiteInterpolation, VelocityOfInterpolantMatchesTruth) {
  const Ascent a;
  const HermiteTrack ht(make_track(a, 10.0, false), 0.5);
  for (double t = 0.31; t < 9.7; t += 0.37) {
    const TrackSample s = ht.sample(at(t));
    EXPECT_LT((s.vel_enu - a.vel(since(at(t)))).norm(), 0.02) << t;
  }
}

TEST(HermiteInterpolation, NothingIsProducedAcrossAGap) {
  const Ascent a;
  // A 2 s hole: epochs at 5.0 and 7.0 s are the gap's edges.
  const HermiteTrack ht(make_track(a, 12.0, false, 5.0, 7.0), 0.5);
  for (double t = 5.0005; t < 7.0; t += 0.001) {
    const TrackSample s = ht.sample(at(t));
    ASSERT_EQ(s.status, TrackSampleStatus::in_gap) << t;
    EXPECT_NEAR(s.interval_s, 2.0, 1e-9);
    EXPECT_EQ(ht.epoch_time(s.segment), at(5.0));
  }
  // Edges: exactly at the edge epochs, and just outside the hole on either side.
  EXPECT_EQ(ht.sample(at(5.0)).status, TrackSampleStatus::ok);
  EXPECT_EQ(ht.sample(at(7.0)).status, TrackSampleStatus::ok);
  EXPECT_LT(max_error_at_camera_times(ht, a, 4.0, 5.0), 1e-3);
  EXPECT_LT(max_error_at_camera_times(ht, a, 7.0, 8.0), 1e-3);
  EXPECT_LT((ht.sample(at(4.9995)).enu - a.pos(since(at(4.9995)))).norm(), 1e-3);
  EXPECT_LT((ht.sample(at(7.0005)).enu - a.pos(since(at(7.0005)))).norm(), 1e-3);
}

TEST(HermiteInterpolation, FiniteDifferenceTangentsDoNotCrossAGap) {
  // Straight-line motion at 3 m/s up before the gap, at 1 m/s east after it, with a 50 m jump
  // across the gap: any tangent that looked across the gap would be wildly wrong.
  LampTrack tr;
  for (int k = 0; k <= 10; ++k)
    tr.epochs.push_back({at(0.1 * k), {0, 0, 3.0 * 0.1 * k}, {0.01, 0.01, 0.01}, 1});
  for (int k = 0; k <= 10; ++k)
    tr.epochs.push_back({at(3.0 + 0.1 * k), {50 + 0.1 * k, 0, 0}, {0.01, 0.01, 0.01}, 1});
  const HermiteTrack ht(tr, 0.5);
  EXPECT_LT((ht.tangent(10) - Eigen::Vector3d(0, 0, 3)).norm(), 1e-9);  // last before the gap
  EXPECT_LT((ht.tangent(11) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-9);  // first after it
  EXPECT_LT((ht.tangent(0) - Eigen::Vector3d(0, 0, 3)).norm(), 1e-9);   // track start
  const TrackSample s = ht.sample(at(0.95));
  EXPECT_LT((s.enu - Eigen::Vector3d(0, 0, 2.85)).norm(), 1e-9);
}

TEST(HermiteInterpolation, UnevenSpacingStaysAccurate) {
  // Dropped epochs (float fixes filtered out) leave 0.2–0.3 s intervals below max_gap_s.
  const Ascent a;
  LampTrack tr = make_track(a, 10.0, false);
  LampTrack thinned;
  for (std::size_t i = 0; i < tr.epochs.size(); ++i)
    if (i % 7 != 3 && i % 11 != 5) thinned.epochs.push_back(tr.epochs[i]);
  const HermiteTrack ht(thinned, 0.5);
  EXPECT_LT(max_error_at_camera_times(ht, a, 0.0, 10.0), 2e-3);
}

TEST(HermiteInterpolation, NoExtrapolation) {
  const Ascent a;
  const HermiteTrack ht(make_track(a, 2.0, false), 0.5);
  EXPECT_EQ(ht.sample(at(-0.0001)).status, TrackSampleStatus::before_track);
  EXPECT_EQ(ht.sample(at(2.0001)).status, TrackSampleStatus::after_track);
  EXPECT_EQ(ht.sample(at(2.0)).status, TrackSampleStatus::ok);
  EXPECT_STREQ(to_string(TrackSampleStatus::in_gap), "in_gap");
}

TEST(HermiteInterpolation, SingleEpochTrackAnswersOnlyAtThatEpoch) {
  LampTrack tr;
  tr.epochs.push_back({at(1.0), {1, 2, 3}, {0.01, 0.01, 0.02}, 1});
  const HermiteTrack ht(tr, 0.5);
  EXPECT_EQ(ht.sample(at(1.0)).status, TrackSampleStatus::ok);
  EXPECT_EQ(ht.sample(at(1.0)).enu, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(ht.sample(at(1.001)).status, TrackSampleStatus::after_track);
}

TEST(HermiteInterpolation, BadInput) {
  LampTrack empty;
  try {
    HermiteTrack ht(empty, 0.5, "out/gnss/lamp_track.csv");
    FAIL() << "empty track accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "out/gnss/lamp_track.csv");
    EXPECT_NE(std::string(e.what()).find("no epochs"), std::string::npos) << e.what();
  }
  const Ascent a;
  LampTrack tr = make_track(a, 1.0, false);
  std::swap(tr.epochs[3], tr.epochs[4]);
  try {
    HermiteTrack ht(tr, 0.5);
    FAIL() << "unordered track accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.field(), "utc");
    EXPECT_NE(e.reason().find("epoch 5"), std::string::npos) << e.what();
    EXPECT_NE(e.reason().find("strictly increasing"), std::string::npos) << e.what();
  }
  tr = make_track(a, 1.0, false);
  tr.epochs[2].utc = tr.epochs[1].utc;  // duplicate time
  EXPECT_THROW(HermiteTrack(tr, 0.5), Error);
  tr = make_track(a, 1.0, false);
  tr.epochs[2].enu.z() = std::nan("");
  EXPECT_THROW(HermiteTrack(tr, 0.5), Error);
  try {
    HermiteTrack ht(make_track(a, 1.0, false), 0.0);
    FAIL() << "max_gap_s 0 accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_EQ(e.field(), "gnss.max_gap_s");
  }
}

}  // namespace
}  // namespace rangecal
