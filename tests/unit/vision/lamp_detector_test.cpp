// Lamp detector acceptance (docs/accuracy_analysis.md, Quality bars): centroid accuracy on rendered 1280×800
// frames, saturated cores, no false lamp over 1,000 lamp-free frames with hot pixels and a static light,
// motion disambiguation, statuses, and thread-count independence.
#include <gtest/gtest.h>

#include <tbb/parallel_for.h>

#include <cmath>

#include "vision/detection/lamp_detector.hpp"
#include "vision/frames/frame_renderer.hpp"

using namespace rangecal;

namespace {

FrameRenderSettings sky_1280x800(int bits, double read_noise) {
  FrameRenderSettings st;
  st.width = 1280;
  st.height = 800;
  st.bits = bits;
  st.sky_level = bits == 8 ? 40 : 400;
  st.sky_gradient_u = 0.01;  // 13 DN across the frame
  st.sky_gradient_v = -0.02;
  st.read_noise = read_noise;
  return st;
}

// One frame through the real decision path: the sequence pass over a sequence of one frame.
LampDetection decide_one_frame(const cv::Mat& img, int bits, const LampDetectorOptions& opt) {
  return resolve_lamp_sequence({find_lamp_candidates(img, bits, opt)}, opt).front();
}

struct ErrorStats {
  double rms_u = 0, rms_v = 0, bias_u = 0, bias_v = 0;
  int n = 0, missed = 0;
};

// Renders `n` frames with the lamp at random sub-pixel positions and PSF σ in [0.8, 2] and
// compares the detector's position with the truth.
ErrorStats centroid_errors(int n, double snr, int bits, bool saturate, std::uint64_t seed) {
  FrameRenderSettings st = sky_1280x800(bits, 3.0);
  RenderRandom rng(seed);
  LampDetectorOptions opt;
  ErrorStats s;
  double su2 = 0, sv2 = 0, su = 0, sv = 0;
  std::vector<PsfSpot> lamps(static_cast<std::size_t>(n));
  for (PsfSpot& lamp : lamps) {
    lamp.u = 40 + rng.uniform() * 1200;
    lamp.v = 40 + rng.uniform() * 720;
    lamp.sigma_px = 0.8 + 1.2 * rng.uniform();
    const double sat = std::ldexp(1.0, bits) - 1;
    lamp.peak = saturate ? (3.0 + 5.0 * rng.uniform()) * sat : snr * st.read_noise;
  }
  std::vector<LampDetection> dets(static_cast<std::size_t>(n));
  tbb::parallel_for(0, n, [&](int i) {
    const cv::Mat img = render_frame(st, {lamps[i]}, seed * 1000 + static_cast<std::uint64_t>(i));
    dets[i] = decide_one_frame(img, bits, opt);
  });
  for (int i = 0; i < n; ++i) {
    const PsfSpot& lamp = lamps[i];
    const LampDetection& d = dets[i];
    if (!d.usable()) {
      ++s.missed;
      continue;
    }
    const double du = d.u - lamp.u, dv = d.v - lamp.v;
    su += du;
    sv += dv;
    su2 += du * du;
    sv2 += dv * dv;
    ++s.n;
  }
  s.bias_u = su / s.n;
  s.bias_v = sv / s.n;
  s.rms_u = std::sqrt(su2 / s.n);
  s.rms_v = std::sqrt(sv2 / s.n);
  return s;
}

}  // namespace

TEST(LampDetector, CentroidAccuracyUnsaturatedSnr20) {
  for (const int bits : {8, 16}) {
    const ErrorStats s = centroid_errors(bits == 8 ? 400 : 200, 20.0, bits, false, 11 + bits);
    std::printf("bits %d: n=%d missed=%d rms_u=%.4f rms_v=%.4f bias_u=%.4f bias_v=%.4f\n", bits, s.n,
                s.missed, s.rms_u, s.rms_v, s.bias_u, s.bias_v);
    EXPECT_EQ(s.missed, 0);
    EXPECT_LE(s.rms_u, 0.05);
    EXPECT_LE(s.rms_v, 0.05);
    EXPECT_LE(std::abs(s.bias_u), 0.02);
    EXPECT_LE(std::abs(s.bias_v), 0.02);
  }
}

TEST(LampDetector, CentroidAccuracySaturatedCore) {
  const ErrorStats s = centroid_errors(200, 0, 8, true, 77);
  std::printf("saturated: n=%d missed=%d rms_u=%.4f rms_v=%.4f bias_u=%.4f bias_v=%.4f\n", s.n, s.missed,
              s.rms_u, s.rms_v, s.bias_u, s.bias_v);
  EXPECT_EQ(s.missed, 0);
  EXPECT_LE(std::hypot(s.rms_u, s.rms_v), 0.15);
}

// Acceptance: over 1,000 frames holding only sky, noise, hot pixels and a static distractor, no
// detection is reported as the lamp.
TEST(LampDetector, NoFalseLampInThousandLampFreeFrames) {
  FrameRenderSettings st = sky_1280x800(8, 2.5);
  st.gain = 4.0;  // shot noise too
  st.hot_pixels = random_hot_pixels(st.width, st.height, 40, 30, 215, 5);
  st.static_lights = {{911.4, 233.7, 1.4, 120.0}};
  std::vector<ImageFrame> frames(1000);
  tbb::parallel_for(0, 1000, [&](int i) {  // rendering is the slow part; seeds make it deterministic
    frames[i].frame = i;
    frames[i].utc = UtcTime{1'780'000'000'000'000'000ll + i * 100'000'000ll};
    frames[i].image = render_frame(st, {}, 5000 + static_cast<std::uint64_t>(i));
    frames[i].bits = 8;
  });
  const auto det = detect_lamp(frames, LampDetectorOptions{}, 0);
  ASSERT_EQ(det.size(), 1000u);
  int n_static = 0;
  for (const auto& d : det) {
    EXPECT_FALSE(d.usable()) << "frame " << d.frame << " " << d.status << " at " << d.u << "," << d.v;
    n_static += d.status == lamp_status::kStatic;
  }
  EXPECT_GT(n_static, 900);  // the distractor is seen, and rejected as static
}

TEST(LampDetector, MovingLampAmongDistractorsAndTransientLight) {
  FrameRenderSettings st = sky_1280x800(8, 2.5);
  st.hot_pixels = random_hot_pixels(st.width, st.height, 30, 60, 215, 9);
  st.static_lights = {{300.2, 500.9, 1.3, 150.0}};
  const int n = 120;
  std::vector<ImageFrame> frames(n);
  std::vector<PsfSpot> truth(n);
  for (int i = 0; i < n; ++i) {
    truth[i] = {600.0 + 0.4 * i, 700.0 - 5.1 * i, 1.2, 90.0};  // an ascent: up the image
    std::vector<PsfSpot> spots{truth[i]};
    // Frames 50–59: a second, moving light (a bird, an aircraft) near the lamp.
    if (i >= 50 && i < 60) spots.push_back({truth[i].u + 35.0 + 2.0 * i, truth[i].v + 20.0, 1.5, 110.0});
    frames[i].frame = 10 * i;
    frames[i].utc = UtcTime{1'780'000'000'000'000'000ll + i * 100'000'000ll};
    frames[i].image = render_frame(st, spots, 900 + static_cast<std::uint64_t>(i));
    frames[i].bits = 8;
  }
  const auto det1 = detect_lamp(frames, LampDetectorOptions{}, 1);
  const auto det2 = detect_lamp(frames, LampDetectorOptions{}, 2);
  EXPECT_EQ(format_detections_csv(det1), format_detections_csv(det2));  // thread-count independent
  for (int i = 0; i < n; ++i) {
    const auto& d = det1[i];
    ASSERT_TRUE(d.usable()) << "frame " << i << " " << d.status;
    EXPECT_NEAR(d.u, truth[i].u, 0.2) << i;
    EXPECT_NEAR(d.v, truth[i].v, 0.2) << i;
    if (i >= 50 && i < 60)
      EXPECT_EQ(d.status, lamp_status::kOkByMotion) << i;
    else
      EXPECT_EQ(d.status, lamp_status::kOk) << i;
  }
  // Without motion context the frames with two lights are ambiguous.
  const LampDetectorOptions opt;
  EXPECT_EQ(decide_one_frame(frames[55].image, 8, opt).status, lamp_status::kAmbiguous);
}

TEST(LampDetector, StatusesForHotPixelFaintLampEdgeAndEmptyFrames) {
  FrameRenderSettings st = sky_1280x800(16, 3.0);
  st.sky_gradient_u = st.sky_gradient_v = 0;
  const LampDetectorOptions opt;
  auto status = [&](const FrameRenderSettings& s, const std::vector<PsfSpot>& spots) {
    return decide_one_frame(render_frame(s, spots, 3), 16, opt).status;
  };
  EXPECT_EQ(status(st, {}), lamp_status::kNoLamp);
  FrameRenderSettings hot = st;
  hot.hot_pixels = {{500, 300, 400.0}};
  EXPECT_EQ(status(hot, {}), lamp_status::kHotPixel);
  EXPECT_EQ(status(st, {{640.3, 400.2, 1.2, 3.0 * 7}}), lamp_status::kLowSnr);  // SNR 7 < 10
  EXPECT_EQ(status(st, {{0.6, 400.2, 1.2, 300}}), lamp_status::kEdge);
  EXPECT_EQ(status(st, {{640.3, 400.2, 1.2, 300}}), lamp_status::kOk);
  st.bits = 12;
  EXPECT_EQ(decide_one_frame(render_frame(st, {{640.3, 400.2, 1.5, 20000}}, 3), 12, opt).status,
            lamp_status::kOkSaturated);
}
