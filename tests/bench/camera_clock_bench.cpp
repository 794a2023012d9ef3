// Benchmarks of a camera's clock found from its track (pipeline/steps/camera_clock.hpp,
// docs/alignment.md "Cameras without time code"; docs/performance.md): 120 s of labels at 50 fps
// (6,000 frames) against a 300-s lamp track, the clock 40 s and 1e-4 off (tests/support/clock_labels.hpp).
// The reference, in the same run: one bundle of the same camera from the same labels at their true
// times — the calibration a camera with time code gets, which the clock's search and refinement
// add to.
#include <benchmark/benchmark.h>

#include "optim/bundle/bundle_adjustment.hpp"
#include "support/clock_labels.hpp"
#include "vision/calibration/dlt.hpp"

namespace rangecal {
namespace {

struct Scene {
  Camera camera = test::wide_camera();
  LampTrack track = test::lamp_track(300);
  test::Labels labels = test::labels_of(camera, test::kClockStart + 60, 40, 1e-4, 50, 6000, 0.5, 1);
};

const Scene& scene() {
  static const Scene s;
  return s;
}

void BM_CameraClock(benchmark::State& state) {
  const Scene& s = scene();
  const HermiteTrack track(s.track, 0.5);
  for (auto _ : state)
    benchmark::DoNotOptimize(
        estimate_camera_clock(track, s.labels.labels, test::sensor_of(s.camera), {}, "bench"));
  state.counters["labels"] = static_cast<double>(s.labels.labels.size());
}
BENCHMARK(BM_CameraClock)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_BundleAtTrueTimes(benchmark::State& state) {
  const Scene& s = scene();
  const HermiteTrack track(s.track, 0.5);
  std::vector<BundleObservation> obs;
  std::vector<PointCorrespondence> pts;
  for (std::size_t i = 0; i < s.labels.labels.size(); ++i) {
    const TrackSample t = track.sample(test::utc(s.labels.truth_s[i]));
    if (t.status != TrackSampleStatus::ok) continue;
    BundleObservation o;
    o.world = t.enu;
    o.world_cov = t.sd_enu.cwiseProduct(t.sd_enu).asDiagonal();
    o.pixel = s.labels.labels[i].uv;
    obs.push_back(o);
    pts.push_back({o.world, o.pixel});
  }
  BundleOptions options;
  options.free = {"f", "u0", "v0", "k1", "k2", "pose"};
  options.pixel_sigma_px = 1;
  for (auto _ : state) {
    const Camera initial = dlt_calibrate(pts, test::sensor_of(s.camera)).camera;
    benchmark::DoNotOptimize(bundle_adjust(initial, obs, options));
  }
}
BENCHMARK(BM_BundleAtTrueTimes)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace rangecal
