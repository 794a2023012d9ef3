// Align-stage speed (docs/alignment.md): a 20 Hz, 1-hour lamp track (72,000 epochs, no .pos velocity, so
// tangents come from finite differences) against 1,000 and 100,000 frame stamps spread over the
// hour (a 1000 fps camera exporting every n-th frame).
#include <benchmark/benchmark.h>

#include <cmath>

#include "gnss/track/hermite_interpolation.hpp"
#include "pipeline/steps/align_frames.hpp"

namespace rangecal {
namespace {

const UtcTime kT0 = utc_from_civil(2026, 5, 10, 3, 0, 0, 0);

LampTrack hour_track_20hz() {
  LampTrack tr;
  tr.epochs.reserve(72'001);
  for (int k = 0; k <= 72'000; ++k) {
    const double t = k * 0.05;
    LampEpoch e;
    e.utc = UtcTime{kT0.ns + std::int64_t{50'000'000} * k};
    // Repeated 60 s ascents and descents with a horizontal wobble.
    const double phase = std::fmod(t, 120.0);
    const double z = phase < 60 ? 2 + 1.5 * phase : 92 - 1.5 * (phase - 60);
    e.enu = {0.3 * std::sin(2.5 * t), 0.2 * std::cos(1.6 * t), z};
    e.sd_enu = {0.01, 0.01, 0.02};
    e.quality = 1;
    tr.epochs.push_back(e);
  }
  return tr;
}

std::vector<FrameStamp> frames_over_hour(std::int64_t count) {
  // 1000 fps camera; export step chosen so `count` frames span the hour.
  const std::int64_t step = 3'600'000 / count;
  std::vector<FrameStamp> f;
  f.reserve(static_cast<std::size_t>(count));
  for (std::int64_t i = 0; i < count; ++i)
    f.push_back({i * step, UtcTime{kT0.ns + 370'000 + i * step * 1'000'000}});
  return f;
}

void BM_AlignFrames(benchmark::State& state) {
  const LampTrack tr = hour_track_20hz();
  const auto frames = frames_over_hour(state.range(0));
  AlignOptions opt;
  opt.max_frame_offset_s = 0.005;
  std::size_t aligned = 0;
  for (auto _ : state) {
    const AlignResult r = align_frames(tr, frames, opt);
    aligned = r.aligned.size();
    benchmark::DoNotOptimize(r.aligned.data());
  }
  state.counters["epochs"] = static_cast<double>(tr.epochs.size());
  state.counters["aligned"] = static_cast<double>(aligned);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(frames.size()));
}
BENCHMARK(BM_AlignFrames)->Arg(1'000)->Arg(100'000)->Unit(benchmark::kMillisecond);

void BM_HermiteSample(benchmark::State& state) {
  const HermiteTrack ht(hour_track_20hz(), 0.5);
  std::int64_t i = 0;
  for (auto _ : state) {
    const TrackSample s = ht.sample(UtcTime{kT0.ns + (i * 7'919'003) % 3'600'000'000'000});
    benchmark::DoNotOptimize(s.enu);
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_HermiteSample);

}  // namespace
}  // namespace rangecal
