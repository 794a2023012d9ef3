// A camera without time code (pipeline/steps/camera_clock.hpp): a simulated camera whose nominal frame
// times are 40 s and 1e-4 off the truth, its labels drawn from the true path with noise; the offset
// and rate are recovered so that every frame's time is within 2 ms of its truth, and the σ covers the
// error. The truth is the simulation's; the path is written here, not by the simulator.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "config/deterministic_random.hpp"
#include "pipeline/steps/camera_clock.hpp"
#include "support/clock_labels.hpp"
#include "support/expect_error.hpp"
#include "vision/camera/camera_model.hpp"

namespace rangecal {
namespace {

using test::kClockStart;
using test::Labels;
using test::labels_of;
using test::lamp_at;
using test::lamp_track;
using test::sensor_of;
using test::utc;
using test::wide_camera;
constexpr double kStart = kClockStart;

TEST(CameraClock, RecoversFortySecondsAndOneInTenThousand) {
  const Camera cam = wide_camera();
  const HermiteTrack track(lamp_track(300), 0.5);
  for (std::uint64_t seed : {1, 2, 3}) {
    const double offset = 40.0 + 0.0137 * static_cast<double>(seed), rate = 1e-4;
    const Labels l = labels_of(cam, kStart + 60, offset, rate, 50, 6000, 0.5, seed);
    ASSERT_GT(l.labels.size(), 3000u);
    const CameraClock c = estimate_camera_clock(track, l.labels, sensor_of(cam), {}, "sim");
    double worst = 0;
    for (std::size_t i = 0; i < l.labels.size(); ++i)
      worst = std::max(
          worst, std::abs(1e-9 * static_cast<double>(c.time_of(l.labels[i].nominal).ns) - l.truth_s[i]));
    std::printf(
        "seed %d: worst frame-time error %.3f ms, offset %+.3f ms (σ %.3f, the track's share %.3f), rate "
        "%+.2f "
        "ppm off (σ %.2f)\n",
        static_cast<int>(seed), 1e3 * worst, 1e3 * (c.offset_s - offset), 1e3 * c.offset_sd_s,
        1e3 * c.track_sd_s, 1e6 * (c.rate - rate), 1e6 * c.rate_sd);
    EXPECT_LT(worst, 0.002) << "seed " << seed;
    EXPECT_NEAR(c.offset_s, offset, 0.002);
    EXPECT_NEAR(c.rate, rate, 2e-5);
    // The stated σ covers the error: the blocks' part (the track here is exact, so its share, the
    // fixes' 1 cm sd along the path over the speed, is all margin; 4σ: three missions).
    const double blocks_sd = std::sqrt(c.offset_sd_s * c.offset_sd_s - c.track_sd_s * c.track_sd_s);
    EXPECT_LT(std::abs(c.offset_s - offset), 4 * blocks_sd + 1e-4) << "σ " << blocks_sd;
    EXPECT_GT(c.track_sd_s, 0.002);  // 1 cm along a path flown at 1–5 m/s
    EXPECT_LT(c.track_sd_s, 0.010);
    EXPECT_FALSE(c.variable_frame_rate);
    EXPECT_GT(c.search_other_score_px, 1.5 * c.search_best_score_px);
  }
}

// A rolling shutter: row v exposed (v/(H−1) − ½)·20 ms after the frame's time; the readout is found
// with the clock, and the labels' times then match their truth.
TEST(CameraClock, RecoversARollingShutterReadout) {
  const Camera cam = wide_camera();
  const HermiteTrack track(lamp_track(300), 0.5);
  const double readout = 0.020, offset = 31.5;
  DeterministicRandom rng(11);
  Labels l;
  for (int k = 0; k < 6000; ++k) {
    const double frame_truth = kStart + 60 + k / 50.0;
    // The row's delay depends on the row the lamp lands in: two passes settle it.
    Eigen::Vector2d uv;
    double t = frame_truth;
    for (int pass = 0; pass < 3; ++pass) {
      if (!project(cam, lamp_at(t), &uv)) break;
      t = frame_truth + readout * (uv.y() / (cam.intr.height_px - 1) - 0.5);
    }
    if (!project(cam, lamp_at(t), &uv)) continue;
    uv += 0.5 * Eigen::Vector2d(rng.normal(), rng.normal());
    if (uv.x() < 0 || uv.y() < 0 || uv.x() > cam.intr.width_px - 1 || uv.y() > cam.intr.height_px - 1)
      continue;
    l.labels.push_back({k, utc(frame_truth - offset), uv});
    l.truth_s.push_back(t);
  }
  ClockSearchOptions o;
  o.estimate_readout = true;
  const CameraClock c = estimate_camera_clock(track, l.labels, sensor_of(cam), o, "sim");
  double worst = 0;
  for (std::size_t i = 0; i < l.labels.size(); ++i)
    worst = std::max(
        worst, std::abs(1e-9 * static_cast<double>(c.label_time(l.labels[i].nominal, l.labels[i].uv.y()).ns) -
                        l.truth_s[i]));
  std::printf("readout %.2f ms (σ %.2f), true 20; worst label-time error %.3f ms\n", 1e3 * c.readout_s,
              1e3 * c.readout_sd_s, 1e3 * worst);
  EXPECT_NEAR(c.readout_s, readout, 0.002);
  EXPECT_LT(worst, 0.002);
  EXPECT_NEAR(c.offset_s, offset, 0.002);
}

// A phone's variable frame rate: one 20-s stretch whose frames run 30 ms late is flagged.
TEST(CameraClock, FlagsAVariableFrameRate) {
  const Camera cam = wide_camera();
  const HermiteTrack track(lamp_track(300), 0.5);
  Labels l = labels_of(cam, kStart + 60, 25.0, 0, 30, 3600, 0.5, 7);
  for (std::size_t i = 0; i < l.labels.size(); ++i) {
    const double since = l.truth_s[i] - (kStart + 60);
    if (since > 40 && since < 60)
      l.labels[i].uv = [&] {
        Eigen::Vector2d uv;
        project(cam, lamp_at(l.truth_s[i] + 0.03), &uv);
        return uv;
      }();
  }
  const CameraClock c = estimate_camera_clock(track, l.labels, sensor_of(cam), {}, "sim");
  EXPECT_TRUE(c.variable_frame_rate);
  EXPECT_GT(c.worst_block_deviation_s, 0.015);
}

TEST(CameraClock, RefusesTooFewLabelsAndNoOverlap) {
  const Camera cam = wide_camera();
  const HermiteTrack track(lamp_track(60), 0.5);
  const Labels few = labels_of(cam, kStart + 10, 5, 0, 1, 10, 0.5, 1);
  Error e =
      test::expect_error([&] { estimate_camera_clock(track, few.labels, sensor_of(cam), {}, "few.csv"); });
  EXPECT_EQ(e.exit_code(), 3);
  EXPECT_EQ(e.file(), "few.csv");
  // 200 s of labels against 60 s of track: no offset puts half of them inside it.
  const Labels longer = labels_of(cam, kStart, 0, 0, 10, 2000, 0.5, 1);
  e = test::expect_error(
      [&] { estimate_camera_clock(track, longer.labels, sensor_of(cam), {}, "long.csv"); });
  EXPECT_NE(std::string(e.what()).find("half of the labels"), std::string::npos);
}

}  // namespace
}  // namespace rangecal
