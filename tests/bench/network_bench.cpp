// Benchmarks of the network bundle (optim/network, docs/optimisation.md "Network bundle";
// docs/performance.md): 2 cameras × 1,000 epochs (target < 100 ms) and 8 cameras × 20,000 epochs
// on one thread (target < 3 s, with peak memory), and how the time grows with epochs and cameras.
// Each run is the whole production path: robust solve, outlier tests, final solve, joint
// covariance. Synthetic geometry: seed-002-like cameras (1280×800, 20 µm, 135 mm) on a 64 m circle
// round the flight volume, every lamp epoch seen by each camera whose image it falls in, PPK fixes
// with 1 cm noise, 0.05 px centroids.
#include <benchmark/benchmark.h>

#include <sys/resource.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "optim/network/network_adjustment.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

struct SyntheticNetwork {
  std::vector<Camera> truth;
  std::vector<NetworkCamera> cameras;
  std::vector<NetworkPoint> points;
  std::vector<NetworkObservation> observations;
};

SyntheticNetwork make_network(int n_cameras, int n_epochs) {
  SyntheticNetwork n;
  const Vector3d aim(0, 0, 20);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> N01;
  std::uniform_real_distribution<double> U(-1, 1);
  for (int c = 0; c < n_cameras; ++c) {
    const double a = 2 * M_PI * c / n_cameras + 0.3;
    const Camera t = test::range_camera_at("cam" + std::to_string(c + 1),
                                           aim + Vector3d(64 * std::cos(a), 64 * std::sin(a), -18.5), aim);
    n.truth.push_back(t);
    NetworkCamera nc;
    nc.initial = t;  // started a little off, as from the per-camera bundle
    nc.initial.intr.f_mm *= 1.002;
    const Vector3d C = t.pose.center() + Vector3d(0.03, -0.02, 0.04);
    nc.initial.pose.R =
        Eigen::AngleAxisd(3e-4, Vector3d(1, -1, 0.5).normalized()).toRotationMatrix() * t.pose.R;
    nc.initial.pose.T = -nc.initial.pose.R * C;
    nc.options.free = {"f", "k1", "pose"};
    n.cameras.push_back(nc);
  }
  // A lamp climbing and sinking through the common field of view (±2.5 m across, ±2 m in height).
  for (int k = 0; k < n_epochs; ++k) {
    const Vector3d X = aim + Vector3d(2.5 * U(rng), 2.5 * U(rng), 2.0 * U(rng));
    NetworkPoint p;
    p.prior_cov = Matrix3d::Identity() * 1e-4;
    p.prior_enu = X + 0.01 * Vector3d(N01(rng), N01(rng), N01(rng));
    p.source = "epoch " + std::to_string(k);
    bool seen = false;
    for (int c = 0; c < n_cameras; ++c) {
      Vector2d uv;
      if (!project(n.truth[static_cast<std::size_t>(c)], X, &uv)) continue;
      if (uv.x() < 0 || uv.x() > 1280 || uv.y() < 0 || uv.y() > 800) continue;
      NetworkObservation o;
      o.camera = static_cast<std::size_t>(c);
      o.point = n.points.size();
      o.pixel = uv + 0.05 * Vector2d(N01(rng), N01(rng));
      o.pixel_sigma_px = 0.05;
      n.observations.push_back(o);
      seen = true;
    }
    if (seen) n.points.push_back(p);
  }
  return n;
}

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

// Arguments: cameras, epochs. One Ceres thread (NetworkOptions::num_threads default).
void BM_Network(benchmark::State& state) {
  const SyntheticNetwork n = make_network(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  NetworkResult r;
  for (auto _ : state) {
    r = network_adjust(n.cameras, n.points, n.observations);
    benchmark::DoNotOptimize(r.statistics.chi2);
  }
  double f_err = 0;
  for (std::size_t c = 0; c < n.truth.size(); ++c)
    f_err = std::max(f_err, std::abs(r.cameras[c].calibration.camera.intr.f_mm - n.truth[c].intr.f_mm) /
                                r.cameras[c].calibration.sigma(CameraParameter::f));
  state.counters["observations"] = static_cast<double>(n.observations.size());
  state.counters["iterations"] = r.statistics.iterations;
  state.counters["variance_factor"] = r.statistics.variance_factor;
  state.counters["max_f_err_sigma"] = f_err;  // sanity: the solve converged to the truth
  state.counters["peak_rss_MB"] = peak_rss_mb();
}
BENCHMARK(BM_Network)
    ->ArgNames({"cameras", "epochs"})
    ->Args({2, 1000})  // target < 100 ms
    ->Args({2, 250})   // growth with epochs
    ->Args({2, 4000})
    ->Args({2, 16000})
    ->Args({4, 1000})  // growth with cameras
    ->Args({8, 1000})
    ->Args({8, 5000})
    ->Args({8, 20000})  // target < 3 s
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace
}  // namespace rangecal
