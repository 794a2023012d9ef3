// Speed of the calibration initialisers on 1,000 points (docs/accuracy_analysis.md, Quality bars style:
// benchmarks, not timed tests). Scene: the paper-like range camera (1280×800, 135 mm, ≈ 64 m) with k1, points
// on its ascents, 0.1 px pixel noise; for RANSAC, 10 % gross outliers.
#include <benchmark/benchmark.h>

#include "config/deterministic_random.hpp"
#include "support/synthetic_camera.hpp"
#include "vision/calibration/dlt.hpp"
#include "vision/calibration/planar_calibration.hpp"
#include "vision/calibration/tsai.hpp"

namespace rangecal {
namespace {

std::vector<PointCorrespondence> thousand_points(double k1, double outlier_fraction) {
  const Camera cam = test::range_camera(k1);
  test::RangeSceneOptions opt;
  opt.points_per_ascent = 332;  // 3 × 332 + 4 poles = 1,000
  auto pts = test::observe(cam, test::range_world_points(cam, opt), 0.1, 0.0, 3);
  DeterministicRandom rng(9);
  for (auto& p : pts)
    if (rng.uniform() < outlier_fraction)
      p.pixel += Eigen::Vector2d(rng.uniform(-40, 40), rng.uniform(-40, 40));
  return pts;
}

void BM_Tsai1000(benchmark::State& state) {
  const auto pts = thousand_points(-2e-4, 0.0);
  const Camera cam = test::range_camera();
  TsaiSensor s{cam.intr.width_px, cam.intr.height_px, cam.intr.dx_mm,
               cam.intr.dy_mm,    cam.intr.u0_px,     cam.intr.v0_px};
  for (auto _ : state) benchmark::DoNotOptimize(tsai_calibrate(pts, s));
  state.counters["points"] = pts.size();
}
BENCHMARK(BM_Tsai1000)->Unit(benchmark::kMillisecond);

void BM_DltRansac1000(benchmark::State& state) {
  const auto pts = thousand_points(0.0, 0.1);
  const Camera cam = test::range_camera();
  const SensorGeometry s{cam.intr.width_px, cam.intr.height_px, cam.intr.dx_mm, cam.intr.dy_mm};
  DltOptions opt;
  opt.inlier_threshold_px = 1.0;
  int iters = 0;
  for (auto _ : state) {
    const DltResult r = dlt_calibrate(pts, s, opt);
    iters = r.ransac_iterations;
    benchmark::DoNotOptimize(r);
  }
  state.counters["points"] = pts.size();
  state.counters["ransac_samples"] = iters;
}
BENCHMARK(BM_DltRansac1000)->Unit(benchmark::kMillisecond);

void BM_DltLinear1000(benchmark::State& state) {
  const auto pts = thousand_points(0.0, 0.0);
  const Camera cam = test::range_camera();
  const SensorGeometry s{cam.intr.width_px, cam.intr.height_px, cam.intr.dx_mm, cam.intr.dy_mm};
  DltOptions opt;
  opt.ransac = false;
  for (auto _ : state) benchmark::DoNotOptimize(dlt_calibrate(pts, s, opt));
  state.counters["points"] = pts.size();
}
BENCHMARK(BM_DltLinear1000)->Unit(benchmark::kMillisecond);

void BM_Planar5x200(benchmark::State& state) {
  const Eigen::Vector3d target(300, 240, 0);
  const Eigen::Vector3d centers[5] = {
      {60, -300, 900}, {700, 200, 850}, {-200, 150, 1000}, {150, 850, 800}, {300, 60, 1100}};
  std::vector<std::vector<PointCorrespondence>> views;
  for (const auto& c : centers) {
    const Camera cam = test::generic_camera(c, target, Distortion{-2e-3, 1e-5});
    views.push_back(test::observe(cam, test::planar_grid(20, 10, 30.0), 0.1, 0.0, 5));
  }
  const SensorGeometry s{640, 480, 0.01, 0.01};
  for (auto _ : state) benchmark::DoNotOptimize(planar_calibrate(views, s));
}
BENCHMARK(BM_Planar5x200)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rangecal
