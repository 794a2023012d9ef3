// Lamp search speed and accuracy (docs/accuracy_analysis.md, Quality bars): full-frame search on 1280×800
// 8-bit frames in memory on one thread vs OpenCV's SimpleBlobDetector on the same frames, both centroid
// errors reported as counters; and the whole detection (candidates + sequence pass) over 1,000 frames on 1
// and 2 threads.
#include <benchmark/benchmark.h>

#include <cmath>
#include <opencv2/core/utility.hpp>
#include <opencv2/features2d.hpp>

#include "vision/detection/lamp_detector.hpp"
#include "vision/frames/frame_renderer.hpp"

using namespace rangecal;

namespace {

struct Scene {
  std::vector<cv::Mat> frames;
  std::vector<PsfSpot> truth;
};

// 64 distinct frames: sky gradient, read + shot noise, a few hot pixels, the lamp at a random
// sub-pixel position with PSF σ 0.8–2 px and peak SNR 20–40.
const Scene& scene() {
  static const Scene s = [] {
    Scene sc;
    FrameRenderSettings st;
    st.width = 1280;
    st.height = 800;
    st.bits = 8;
    st.sky_level = 40;
    st.read_noise = 2.5;
    st.gain = 8;
    st.hot_pixels = random_hot_pixels(st.width, st.height, 10, 60, 200, 1);
    RenderRandom rng(2024);
    for (int i = 0; i < 64; ++i) {
      PsfSpot p{40 + rng.uniform() * 1200, 40 + rng.uniform() * 720, 0.8 + 1.2 * rng.uniform(),
                (20 + 20 * rng.uniform()) * 2.7};
      sc.truth.push_back(p);
      sc.frames.push_back(render_frame(st, {p}, 100 + static_cast<std::uint64_t>(i)));
    }
    return sc;
  }();
  return s;
}

void BM_LampSearch_1280x800_8bit(benchmark::State& state) {
  const Scene& sc = scene();
  const LampDetectorOptions opt;
  double se = 0;
  int n_err = 0, missed = 0;
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++ % sc.frames.size();
    const LampDetection d = resolve_lamp_sequence({find_lamp_candidates(sc.frames[k], 8, opt)}, opt).front();
    benchmark::DoNotOptimize(d.u);
    if (i <= sc.frames.size()) {
      if (!d.usable()) {
        ++missed;
        continue;
      }
      se += std::pow(d.u - sc.truth[k].u, 2) + std::pow(d.v - sc.truth[k].v, 2);
      ++n_err;
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["centroid_rms_px"] = n_err ? std::sqrt(se / (2.0 * n_err)) : NAN;  // per axis
  state.counters["missed"] = missed;
}
BENCHMARK(BM_LampSearch_1280x800_8bit)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

void BM_OpenCvSimpleBlobDetector_1280x800_8bit(benchmark::State& state) {
  cv::setNumThreads(1);
  const Scene& sc = scene();
  cv::SimpleBlobDetector::Params p;
  p.filterByColor = true;
  p.blobColor = 255;  // bright blobs
  p.minThreshold = 60;
  p.maxThreshold = 200;
  p.thresholdStep = 10;
  p.minArea = 2;
  p.maxArea = 500;
  p.filterByCircularity = false;
  p.filterByConvexity = false;
  p.filterByInertia = false;
  p.minRepeatability = 2;
  const auto det = cv::SimpleBlobDetector::create(p);
  double se = 0;
  int n_err = 0, missed = 0;
  std::size_t i = 0;
  std::vector<cv::KeyPoint> kp;
  for (auto _ : state) {
    const std::size_t k = i++ % sc.frames.size();
    det->detect(sc.frames[k], kp);
    benchmark::DoNotOptimize(kp.data());
    if (i <= sc.frames.size()) {
      // Score OpenCV generously: its keypoint nearest to the truth.
      double best = 1e300;
      for (const auto& q : kp)
        best = std::min(best, std::pow(q.pt.x - sc.truth[k].u, 2) + std::pow(q.pt.y - sc.truth[k].v, 2));
      if (best > 25) {
        ++missed;
        continue;
      }
      se += best;
      ++n_err;
    }
  }
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["centroid_rms_px"] = n_err ? std::sqrt(se / (2.0 * n_err)) : NAN;
  state.counters["missed"] = missed;
}
BENCHMARK(BM_OpenCvSimpleBlobDetector_1280x800_8bit)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

// detect_lamp over 1,000 in-memory frames (64 distinct images reused), threads = state.range(0).
void BM_DetectLamp_1000Frames(benchmark::State& state) {
  const Scene& sc = scene();
  std::vector<ImageFrame> frames(1000);
  for (int i = 0; i < 1000; ++i) {
    frames[i].frame = i;
    frames[i].utc = UtcTime{1'780'000'000'000'000'000ll + i * 100'000'000ll};
    frames[i].image = sc.frames[static_cast<std::size_t>(i) % sc.frames.size()];
    frames[i].bits = 8;
  }
  const LampDetectorOptions opt;
  for (auto _ : state) {
    const auto d = detect_lamp(frames, opt, static_cast<int>(state.range(0)));
    benchmark::DoNotOptimize(d.data());
  }
  state.counters["frames_per_s"] =
      benchmark::Counter(1000.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DetectLamp_1000Frames)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
