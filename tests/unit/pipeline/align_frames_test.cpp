#include "pipeline/steps/align_frames.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "config/error.hpp"
#include "pipeline/io/align_record.hpp"
#include "pipeline/io/aligned_csv.hpp"
#include "support/expect_error.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Truth: an accelerating ascent (a(t) = 0.3 + 1.5 sin(πt/2) m/s²) with a horizontal wobble.
Eigen::Vector3d truth_pos(double t) {
  const double w = kPi / 2;
  return {0.3 * std::sin(2 * kPi * 0.4 * t + 0.3), 0.2 * std::cos(2 * kPi * 0.25 * t),
          2.0 + 1.0 * t + 0.15 * t * t + 1.5 * (t / w - std::sin(w * t) / (w * w))};
}
Eigen::Vector3d truth_vel(double t) {
  const double w = kPi / 2;
  return {0.3 * 2 * kPi * 0.4 * std::cos(2 * kPi * 0.4 * t + 0.3),
          -0.2 * 2 * kPi * 0.25 * std::sin(2 * kPi * 0.25 * t),
          1.0 + 0.3 * t + 1.5 * (1 - std::cos(w * t)) / w};
}
double truth_speed(double t) {
  return truth_vel(t).norm();
}

const UtcTime kT0 = utc_from_civil(2026, 5, 10, 3, 0, 0, 0);
UtcTime at_ns(std::int64_t ns) {
  return UtcTime{kT0.ns + ns};
}
double since(UtcTime u) {
  return seconds_between(kT0, u);
}

/// 10 Hz epochs over [0, duration] s, without those strictly inside (hole_from, hole_to) s.
LampTrack make_track(double duration, double hole_from = -1, double hole_to = -1) {
  LampTrack tr;
  for (int k = 0; k * 0.1 <= duration + 1e-9; ++k) {
    const double t = k * 0.1;
    if (t > hole_from + 1e-9 && t < hole_to - 1e-9) continue;
    LampEpoch e;
    e.utc = at_ns(std::int64_t{100'000'000} * k);
    e.enu = truth_pos(t);
    e.sd_enu = {0.01, 0.01, 0.02};
    e.quality = 1;
    tr.epochs.push_back(e);
  }
  return tr;
}

/// A camera at `fps` whose frame 0 is at `start_ns` after kT0; every `step`-th frame exported,
/// frames first..last (camera frame numbers).
std::vector<FrameStamp> make_frames(double fps, std::int64_t start_ns, std::int64_t first, std::int64_t last,
                                    std::int64_t step) {
  std::vector<FrameStamp> f;
  for (std::int64_t n = first; n <= last; n += step)
    f.push_back({n, at_ns(start_ns + static_cast<std::int64_t>(std::llround(n * 1e9 / fps)))});
  return f;
}

/// Independent brute force of steps 1–3 (no gap, no fallback): frames kept per epoch.
std::map<std::int64_t, std::int64_t> brute_force_kept(const LampTrack& tr,
                                                      const std::vector<FrameStamp>& frames,
                                                      double max_offset_s) {
  std::map<std::int64_t, std::int64_t> best;  // frame → |dt| ns
  for (const LampEpoch& e : tr.epochs) {
    std::size_t arg = 0;
    for (std::size_t j = 1; j < frames.size(); ++j)
      if (std::llabs(frames[j].utc.ns - e.utc.ns) < std::llabs(frames[arg].utc.ns - e.utc.ns)) arg = j;
    const std::int64_t d = std::llabs(frames[arg].utc.ns - e.utc.ns);
    if (d > std::llround(max_offset_s * 1e9)) continue;
    if (frames[arg].utc < tr.epochs.front().utc || frames[arg].utc > tr.epochs.back().utc) continue;
    auto it = best.find(frames[arg].frame);
    if (it == best.end() || d < it->second) best[frames[arg].frame] = d;
  }
  return best;
}

TEST(AlignStage, DecimatedFramesPickTheNearestFrameAndInterpolateWithinOneMillimetre) {
  const LampTrack tr = make_track(20.0);
  // 1000 fps camera, every 7th frame exported, frame 0 at 0.29 ms after the first epoch.
  const auto frames = make_frames(1000.0, 290'000, 0, 20'000, 7);
  AlignOptions opt;
  opt.max_frame_offset_s = 0.005;
  const AlignResult r = align_frames(tr, frames, opt);
  const auto expect = brute_force_kept(tr, frames, opt.max_frame_offset_s);
  ASSERT_EQ(r.aligned.size(), expect.size());
  double worst = 0, max_dt = 0, sum_dt = 0, worst_err = 0, worst_vel = 0;
  for (const AlignedFrame& a : r.aligned) {
    worst_vel = std::max(worst_vel, (a.vel_enu - truth_vel(since(a.utc))).norm());
    ASSERT_EQ(expect.count(a.frame), 1u) << a.frame;
    EXPECT_EQ(std::llround(std::fabs(a.dt_s) * 1e9), expect.at(a.frame)) << a.frame;
    EXPECT_EQ(a.frame % 7, 0);
    worst = std::max(worst, (a.enu - truth_pos(since(a.utc))).norm());
    max_dt = std::max(max_dt, std::fabs(a.dt_s));
    sum_dt += std::fabs(a.dt_s);
    worst_err = std::max(worst_err, truth_speed(since(a.utc)) * std::fabs(a.dt_s));
    EXPECT_LT((a.sd_enu - Eigen::Vector3d(0.01, 0.01, 0.02)).norm(), 1e-15);
  }
  EXPECT_LT(worst, 1e-3);
  // The velocity (for the bundle's clock offset) to 2 cm/s: 0.04 mm over a 2 ms offset.
  std::printf("  worst velocity error %.4f m/s\n", worst_vel);
  EXPECT_LT(worst_vel, 0.02);
  EXPECT_EQ(r.report.frames_aligned, r.aligned.size());
  EXPECT_NEAR(r.report.max_abs_dt_s, max_dt, 1e-12);
  EXPECT_NEAR(r.report.mean_abs_dt_s, sum_dt / r.aligned.size(), 1e-12);
  EXPECT_LE(r.report.max_abs_dt_s, 0.0035 + 1e-9);  // half the 7 ms export spacing
  EXPECT_NEAR(r.report.worst_position_error_m, worst_err, 0.02 * worst_err);
  EXPECT_GT(r.report.worst_position_error_m, 1e-3);  // uncorrected, the mismatch would matter
  EXPECT_EQ(r.report.epochs, tr.epochs.size());
  EXPECT_EQ(r.report.epochs_outside_frames, 0u);
}

TEST(AlignStage, BoundaryAlignmentWhenFramesStartAfterAndEndBeforeTheTrack) {
  const LampTrack tr = make_track(20.0);
  // Frames from 5.0013 s to about 12 s: 500 fps, every frame exported.
  const auto frames = make_frames(500.0, 5'001'300'000, 0, 3500, 1);
  const AlignResult r = align_frames(tr, frames, AlignOptions{});
  // Epochs at 5.1 … 12.0 s take part (5.0 is 1.3 ms before the first frame and still within
  // the 5 ms window, so it takes part too).
  const double last_frame_s = since(frames.back().utc);
  std::size_t inside = 0;
  for (const LampEpoch& e : tr.epochs)
    if (since(e.utc) >= 5.0013 - 0.005 && since(e.utc) <= last_frame_s + 0.005) ++inside;
  EXPECT_EQ(r.report.epochs_outside_frames, tr.epochs.size() - inside);
  EXPECT_EQ(r.aligned.size(), inside);
  EXPECT_TRUE(r.rejected.empty());
  EXPECT_EQ(r.aligned.front().frame, 0);  // nearest to the 5.0 s epoch
  EXPECT_NEAR(r.aligned.front().dt_s, 0.0013, 1e-12);
  for (const AlignedFrame& a : r.aligned) EXPECT_LT((a.enu - truth_pos(since(a.utc))).norm(), 1e-3);
}

TEST(AlignStage, FramesBeforeTheTrackStartAreNotExtrapolated) {
  const LampTrack tr = make_track(5.0);
  // 500 fps from 1 s before the track: the first epoch's nearest frame lies 0.3 ms before the
  // track begins; the frame 1.7 ms after it is taken instead.
  const auto frames = make_frames(500.0, -1'000'300'000, 0, 3500, 1);
  ASSERT_EQ(frames[500].utc, at_ns(-300'000));
  const AlignResult r = align_frames(tr, frames, AlignOptions{});
  ASSERT_FALSE(r.aligned.empty());
  EXPECT_EQ(r.aligned.front().frame, 501);
  EXPECT_NEAR(r.aligned.front().dt_s, 0.0017, 1e-12);
  for (const AlignedFrame& a : r.aligned) EXPECT_GE(a.utc, tr.epochs.front().utc);
  EXPECT_TRUE(r.rejected.empty());
  EXPECT_EQ(r.aligned.size(), tr.epochs.size());
}

TEST(AlignStage, OffsetLimitKeepsOnlyCloseFrames) {
  const LampTrack tr = make_track(10.0);
  // 27 fps export: frame-to-epoch offsets sweep 0 … 18.5 ms; the last frame is inside the track.
  const auto frames = make_frames(27.0, 1'000'000, 0, 260, 1);
  AlignOptions opt;
  opt.max_frame_offset_s = 0.005;
  const AlignResult r = align_frames(tr, frames, opt);
  const auto expect = brute_force_kept(tr, frames, opt.max_frame_offset_s);
  ASSERT_EQ(r.aligned.size(), expect.size());
  ASSERT_GT(r.rejected.size(), 0u);
  for (const AlignedFrame& a : r.aligned) {
    EXPECT_EQ(expect.count(a.frame), 1u);
    EXPECT_LE(std::fabs(a.dt_s), 0.005);
  }
  for (const RejectedFrame& x : r.rejected) {
    EXPECT_EQ(x.reason, FrameRejection::offset_exceeded);
    EXPECT_GT(std::fabs(x.dt_s), 0.005);
    EXPECT_NE(x.detail.find("max_frame_offset_s"), std::string::npos);
  }
  EXPECT_EQ(r.report.rejected_offset, r.rejected.size());
  EXPECT_EQ(r.report.frames_picked, r.aligned.size() + r.rejected.size());
  // A wider limit keeps every picked frame.
  opt.max_frame_offset_s = 0.02;
  const AlignResult wide = align_frames(tr, frames, opt);
  EXPECT_TRUE(wide.rejected.empty());
  EXPECT_EQ(wide.aligned.size(), r.report.frames_picked);
  EXPECT_GT(wide.report.max_abs_dt_s, 0.005);
}

TEST(AlignStage, NothingIsProducedAcrossAGap) {
  // A 2 s hole in the track between the epochs at 5.0 s and 7.0 s.
  const LampTrack tr = make_track(12.0, 5.0, 7.0);
  // 20 fps export, every frame 3 ms after a 10 Hz epoch time (and 47 ms before the next).
  const auto frames = make_frames(20.0, 3'000'000, 0, 240, 1);
  const AlignResult r = align_frames(tr, frames, AlignOptions{});
  for (const AlignedFrame& a : r.aligned) {
    const double t = since(a.utc);
    EXPECT_FALSE(t > 5.0 && t < 7.0) << a.frame;
    EXPECT_LT((a.enu - truth_pos(t)).norm(), 1e-3) << a.frame;
  }
  // The 5.0 s epoch's frame (5.003 s) lies in the hole, its other neighbour is 47 ms away.
  ASSERT_EQ(r.rejected.size(), 2u);  // plus the last epoch's frame, 3 ms after the track ends
  EXPECT_EQ(r.rejected[0].frame, 100);
  EXPECT_EQ(r.rejected[0].reason, FrameRejection::in_gap);
  EXPECT_NE(r.rejected[0].detail.find("2.000 s gap"), std::string::npos) << r.rejected[0].detail;
  EXPECT_EQ(r.rejected[1].frame, 240);
  EXPECT_EQ(r.rejected[1].reason, FrameRejection::outside_track);
  EXPECT_EQ(r.report.rejected_gap, 1u);
  EXPECT_EQ(r.report.rejected_outside_track, 1u);
  // The 7.0 s epoch's frame (7.003 s) is just past the hole and is kept.
  bool found = false;
  for (const AlignedFrame& a : r.aligned) found = found || a.frame == 140;
  EXPECT_TRUE(found);
  // 121 epochs − 19 in the hole = 102; minus the two rejected.
  EXPECT_EQ(r.aligned.size(), tr.epochs.size() - 2);
}

TEST(AlignStage, GapEdgeFallsBackToTheFrameOnTheUsableSide) {
  const LampTrack tr = make_track(12.0, 5.0, 7.0);
  // 500 fps, frames 0.7 ms after each epoch time: at the 5.0 s edge the nearest frame lies in the
  // hole, the one 1.3 ms before the epoch is used instead.
  const auto frames = make_frames(500.0, 700'000, 0, 6000, 1);
  const AlignResult r = align_frames(tr, frames, AlignOptions{});
  EXPECT_TRUE(r.rejected.empty());  // also at the track's end: frame 6000 lies after it, 5999 is used
  bool found = false;
  for (const AlignedFrame& a : r.aligned) {
    if (a.frame == 2499) {
      found = true;
      EXPECT_NEAR(a.dt_s, -0.0013, 1e-12);
    }
    EXPECT_FALSE(since(a.utc) > 5.0 && since(a.utc) < 7.0);
  }
  EXPECT_TRUE(found);
}

TEST(AlignStage, ReportAsJson) {
  const LampTrack tr = make_track(3.0);
  const AlignResult r = align_frames(tr, make_frames(1000.0, 400'000, 0, 3000, 3), AlignOptions{});
  AlignRecord record;
  record.cameras["cam1"].report = r.report;
  const nlohmann::json j = align_record_json(record).at("cam1");
  EXPECT_EQ(j.at("frames_aligned").get<std::size_t>(), r.aligned.size());
  EXPECT_DOUBLE_EQ(j.at("max_abs_dt_s").get<double>(), r.report.max_abs_dt_s);
  EXPECT_DOUBLE_EQ(j.at("worst_position_error_m").get<double>(), r.report.worst_position_error_m);
  EXPECT_TRUE(j.contains("rejected_gap"));
}

using test::expect_error;

TEST(AlignStage, BadInput) {
  const LampTrack tr = make_track(2.0);
  const auto frames = make_frames(500.0, 0, 0, 500, 1);
  AlignOptions opt;
  opt.track_source = "out/gnss/lamp_track.csv";
  opt.frames_source = "cam1/timestamps.csv";

  Error e = expect_error([&] { align_frames(LampTrack{}, frames, opt); });
  EXPECT_EQ(e.kind(), ErrorKind::input);
  EXPECT_EQ(e.file(), "out/gnss/lamp_track.csv");

  e = expect_error([&] { align_frames(tr, {}, opt); });
  EXPECT_EQ(e.kind(), ErrorKind::input);
  EXPECT_EQ(e.file(), "cam1/timestamps.csv");

  auto bad = frames;
  bad[10].utc = bad[9].utc;
  e = expect_error([&] { align_frames(tr, bad, opt); });
  EXPECT_EQ(e.kind(), ErrorKind::input);
  EXPECT_EQ(e.field(), "utc");
  EXPECT_NE(e.reason().find("frame 10"), std::string::npos) << e.what();
  EXPECT_NE(e.reason().find("strictly increasing"), std::string::npos) << e.what();

  bad = frames;
  bad[10].frame = 9;
  e = expect_error([&] { align_frames(tr, bad, opt); });
  EXPECT_EQ(e.kind(), ErrorKind::input);
  EXPECT_EQ(e.field(), "frame");

  LampTrack unordered = tr;
  std::swap(unordered.epochs[1], unordered.epochs[2]);
  e = expect_error([&] { align_frames(unordered, frames, opt); });
  EXPECT_EQ(e.kind(), ErrorKind::input);
  EXPECT_EQ(e.file(), "out/gnss/lamp_track.csv");

  opt.max_frame_offset_s = 0;
  e = expect_error([&] { align_frames(tr, frames, opt); });
  EXPECT_EQ(e.kind(), ErrorKind::usage);
  EXPECT_EQ(e.field(), "align.max_frame_offset_s");
}

TEST(AlignedCsv, RoundTripAndDeterministicText) {
  const LampTrack tr = make_track(3.0);
  const AlignResult r = align_frames(tr, make_frames(1000.0, 400'000, 0, 3000, 3), AlignOptions{});
  const auto dir = test::scratch_dir("aligned_csv_round_trip");
  const std::string path = (dir / "cam1" / "aligned.csv").string();
  write_aligned_csv(path, r.aligned);
  const std::string text = test::read_text(path);
  EXPECT_EQ(text.rfind("frame,utc,E,N,U,sdE,sdN,sdU,dt_s,vE,vN,vU\n", 0), 0u);
  const auto back = read_aligned_csv(path);
  ASSERT_EQ(back.size(), r.aligned.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(back[i].frame, r.aligned[i].frame);
    EXPECT_EQ(back[i].utc, r.aligned[i].utc);
    EXPECT_LT((back[i].enu - r.aligned[i].enu).cwiseAbs().maxCoeff(), 5.1e-7);
    EXPECT_LT((back[i].sd_enu - r.aligned[i].sd_enu).cwiseAbs().maxCoeff(), 5.1e-7);
    EXPECT_NEAR(back[i].dt_s, r.aligned[i].dt_s, 5.1e-10);
    EXPECT_LT((back[i].vel_enu - r.aligned[i].vel_enu).cwiseAbs().maxCoeff(), 5.1e-5);
  }
  EXPECT_EQ(format_aligned_csv(back), text);  // re-formatting is byte-identical
  // One hand-checked row.
  AlignedFrame a{42,
                 utc_from_civil(2026, 5, 10, 3, 0, 1, 2'500'000),
                 {1.25, -3.5, 20.0000004},
                 {0.01, 0.01, 0.02},
                 -0.0013,
                 {0.5, -0.25, 2.75}};
  EXPECT_EQ(format_aligned_csv({a}),
            "frame,utc,E,N,U,sdE,sdN,sdU,dt_s,vE,vN,vU\n"
            "42,2026-05-10T03:00:01.002500000Z,1.250000,-3.500000,20.000000,0.010000,0.010000,0.020000,-0."
            "001300000,0.5000,-0.2500,2.7500\n");
}

TEST(AlignedCsv, BadInputNamesFileLineAndField) {
  const std::string head = "frame,utc,E,N,U,sdE,sdN,sdU,dt_s,vE,vN,vU\n";
  const std::string row1 = "1,2026-05-10T03:00:01.000000000Z,1,2,3,0.01,0.01,0.02,0.001,0,0,2\n";
  Error e = expect_error([&] {
    parse_aligned_csv(head + row1 + "2,2026-05-10T03:00:01.1Z,1,x,3,0.01,0.01,0.02,0,0,0,2\n", "a.csv");
  });
  EXPECT_EQ(e.kind(), ErrorKind::input);
  EXPECT_EQ(e.file(), "a.csv");
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.field(), "N");
  e = expect_error(
      [&] { parse_aligned_csv(head + row1 + "2,yesterday,1,2,3,0.01,0.01,0.02,0,0,0,2\n", "a.csv"); });
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.field(), "utc");
  e = expect_error([&] {
    parse_aligned_csv(head + row1 + "1,2026-05-10T03:00:02Z,1,2,3,0.01,0.01,0.02,0,0,0,2\n", "a.csv");
  });
  EXPECT_EQ(e.field(), "frame");
  e = expect_error([&] {
    parse_aligned_csv(head + row1 + "2,2026-05-10T03:00:00Z,1,2,3,0.01,0.01,0.02,0,0,0,2\n", "a.csv");
  });
  EXPECT_EQ(e.field(), "utc");
  e = expect_error([&] {
    parse_aligned_csv(head + row1 + "2,2026-05-10T03:00:02Z,1,2,3,-0.01,0.01,0.02,0,0,0,2\n", "a.csv");
  });
  EXPECT_EQ(e.field(), "sdE");
  e = expect_error([&] { parse_aligned_csv("frame,utc,E,N,U,sdE,sdN,sdU\n", "a.csv"); });
  EXPECT_EQ(e.kind(), ErrorKind::input);
  EXPECT_NE(std::string(e.what()).find("dt_s"), std::string::npos) << e.what();
  e = expect_error(
      [&] { parse_aligned_csv(head + "2,2026-05-10T03:00:02Z,1,2,3,0.01,0.01,0.02,0,0,nan,2\n", "a.csv"); });
  EXPECT_EQ(e.field(), "vN");
  e = expect_error([&] { parse_aligned_csv("frame,utc,E,N,U,sdE,sdN,sdU,dt_s\n", "a.csv"); });
  EXPECT_NE(std::string(e.what()).find("vE"), std::string::npos) << e.what();
  e = expect_error([&] { read_aligned_csv("/nonexistent/cam9/aligned.csv"); });
  EXPECT_EQ(e.kind(), ErrorKind::input);
}

}  // namespace
}  // namespace rangecal
