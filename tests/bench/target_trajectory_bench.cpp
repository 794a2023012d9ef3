// Benchmarks of a target's trajectory (vision/triangulation/target_trajectory.hpp, docs/trajectory.md;
// docs/performance.md "Trajectory"): 8 unsynchronised cameras at 1,000 frames/s for 100 s — 100,000
// labels each, 800,000 in all — each with a 12-parameter calibration covariance, at 1,000 instants a
// second (100,000 instants). The reference, in the same run: the same instants' views triangulated
// as static points (triangulation.hpp without timing, as the intersect stage does) — what the
// trajectory adds is the views' interpolation, their timing term and the velocities.
#include <benchmark/benchmark.h>

#include <random>

#include "support/synthetic_camera.hpp"
#include "vision/triangulation/target_trajectory.hpp"
#include "vision/triangulation/trajectory_smoother.hpp"

namespace rangecal {
namespace {

constexpr std::int64_t kT0 = 1'800'000'000'000'000'000;
constexpr double kSeconds = 100, kFps = 1000;

Eigen::Vector3d target_at(double t) {
  return {40 * std::cos(0.2 * t), 40 * std::sin(0.2 * t), 30 + 0.1 * t};  // 8 m/s on a 40-m circle
}

struct Scene {
  std::vector<TrajectoryCamera> cameras;
  std::vector<UtcTime> instants;
};

const Scene& scene() {
  static const Scene s = [] {
    Scene sc;
    std::mt19937_64 rng(8);
    std::normal_distribution<double> n01(0, 1);
    const std::vector<CameraParameter> params = {
        CameraParameter::f,  CameraParameter::u0, CameraParameter::v0, CameraParameter::k1,
        CameraParameter::wx, CameraParameter::wy, CameraParameter::wz, CameraParameter::CE,
        CameraParameter::CN, CameraParameter::CU, CameraParameter::sx, CameraParameter::k2};
    for (int c = 0; c < 8; ++c) {
      const double a = c * 0.785398;
      TrajectoryCamera cam;
      cam.id = "cam" + std::to_string(c);
      cam.camera = test::range_camera_at(cam.id, {400 * std::cos(a), 400 * std::sin(a), 2}, {0, 0, 35}, 0);
      cam.calibration.parameters = params;
      cam.calibration.covariance = Eigen::MatrixXd::Identity(12, 12) * 1e-8;
      cam.label_sigma_px = 0.5;
      const double start = 1e-4 * c;
      for (int j = 0; j < kSeconds * kFps; ++j) {
        const double t = start + j / kFps;
        TimedLabel l;
        l.t = UtcTime{kT0 + std::llround(t * 1e9)};
        if (!project(cam.camera, target_at(t), &l.uv_px)) continue;
        l.uv_px += 0.5 * Eigen::Vector2d(n01(rng), n01(rng));
        l.timing_sigma_s = 1e-4;
        cam.labels.push_back(l);
      }
      sc.cameras.push_back(std::move(cam));
    }
    sc.instants = trajectory_instants(sc.cameras, kFps);
    return sc;
  }();
  return s;
}

void BM_Trajectory(benchmark::State& state) {
  const Scene& s = scene();
  std::size_t labels = 0;
  for (const auto& c : s.cameras) labels += c.labels.size();
  for (auto _ : state) benchmark::DoNotOptimize(estimate_trajectory(s.cameras, s.instants, nullptr));
  state.counters["labels"] = static_cast<double>(labels);
  state.counters["instants"] = static_cast<double>(s.instants.size());
}
BENCHMARK(BM_Trajectory)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1)->Repetitions(3);

// The same with each camera's label σ estimated from the views (label_variance_components.hpp,
// docs/trajectory.md "Label σ"): the REML over 2,000 of the instants, the calibrations' errors one
// draw common to them (8 × 12 parameters), then the trajectory with the σ found.
void BM_TrajectoryEstimatingLabelSigma(benchmark::State& state) {
  const Scene& s = scene();
  TrajectoryOptions options;
  options.estimate_label_sigma = true;
  for (auto _ : state) benchmark::DoNotOptimize(estimate_trajectory(s.cameras, s.instants, nullptr, options));
  state.counters["instants"] = static_cast<double>(s.instants.size());
}
BENCHMARK(BM_TrajectoryEstimatingLabelSigma)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1)
    ->Repetitions(3);

// The smoother over the trajectory's 100,000 instants (vision/triangulation/trajectory_smoother.hpp):
// q's likelihood search and one Kalman + Rauch–Tung–Striebel pass.
void BM_SmoothTrajectory(benchmark::State& state) {
  const Scene& s = scene();
  const Trajectory tr = estimate_trajectory(s.cameras, s.instants, nullptr);
  for (auto _ : state) {
    Trajectory copy = tr;
    benchmark::DoNotOptimize(smooth_trajectory(&copy));
  }
  state.counters["instants"] = static_cast<double>(tr.points.size());
}
BENCHMARK(BM_SmoothTrajectory)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1)->Repetitions(3);

// The reference: each instant's views (the label nearest in time, no interpolation, no timing)
// triangulated as a static point.
void BM_StaticTriangulationOfTheSameInstants(benchmark::State& state) {
  const Scene& s = scene();
  for (auto _ : state) {
    std::size_t done = 0;
    std::vector<std::size_t> next(s.cameras.size(), 0);
    for (const UtcTime t : s.instants) {
      std::vector<TriangulationView> views;
      for (std::size_t c = 0; c < s.cameras.size(); ++c) {
        const auto& L = s.cameras[c].labels;
        while (next[c] + 1 < L.size() && L[next[c] + 1].t <= t) ++next[c];
        TriangulationView v;
        v.camera = s.cameras[c].camera;
        v.calibration = s.cameras[c].calibration;
        v.uv_px = L[next[c]].uv_px;
        v.pick_sigma_px = 0.5;
        views.push_back(std::move(v));
      }
      done += triangulate_point(views).iterations > 0 ? 1 : 0;
    }
    benchmark::DoNotOptimize(done);
  }
}
BENCHMARK(BM_StaticTriangulationOfTheSameInstants)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1)
    ->Repetitions(3);

}  // namespace
}  // namespace rangecal
