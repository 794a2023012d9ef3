// Benchmarks of the network bundle (optim/network, docs/optimisation.md "Network bundle";
// docs/performance.md): 2 cameras × 1,000 epochs (target < 100 ms) and 8 cameras × 20,000 epochs
// on one thread (target < 3 s, with peak memory), and how the time grows with epochs and cameras.
// Each run is the whole production path: robust solve, outlier tests, final solve, joint
// covariance. Synthetic geometry (tests/support/synthetic_network.hpp): seed-002-like cameras on a
// 64 m circle round the flight volume, every lamp epoch seen by each camera whose image it falls in,
// PPK fixes with 1 cm noise, 0.05 px centroids.
#include <benchmark/benchmark.h>

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "optim/network/network_adjustment.hpp"
#include "optim/network/ppk_error_estimation.hpp"
#include "optim/network/restricted_likelihood.hpp"
#include "support/synthetic_network.hpp"

namespace rangecal {
namespace {

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

// Each benchmark's arguments are (cameras, epochs), timed in ms of wall time with the process's CPU
// time beside it.
void network_sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"cameras", "epochs"})->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
}

// The synthetic network of the benchmark's arguments adjusted under `o` in the timed loop, with the
// peak memory after it; the last result, with the network it came from.
struct TimedNetwork {
  test::SyntheticNetwork network;
  NetworkResult result;
};

TimedNetwork time_network_adjust(benchmark::State& state, const NetworkOptions& o) {
  TimedNetwork t{
      test::synthetic_network(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), 11), {}};
  for (auto _ : state) {
    t.result = network_adjust(t.network.cameras, t.network.points, t.network.observations, o);
    benchmark::DoNotOptimize(t.result.statistics.chi2);
  }
  state.counters["peak_rss_MB"] = peak_rss_mb();
  return t;
}

// Arguments: cameras, epochs. One Ceres thread (NetworkOptions::num_threads default).
void BM_Network(benchmark::State& state) {
  const TimedNetwork t = time_network_adjust(state, NetworkOptions());
  const test::SyntheticNetwork& n = t.network;
  const NetworkResult& r = t.result;
  double f_err = 0;
  for (std::size_t c = 0; c < n.truth.size(); ++c)
    f_err = std::max(f_err, std::abs(r.cameras[c].calibration.camera.intr.f_mm - n.truth[c].intr.f_mm) /
                                r.cameras[c].calibration.sigma(CameraParameter::f));
  state.counters["observations"] = static_cast<double>(n.observations.size());
  state.counters["iterations"] = r.statistics.iterations;
  state.counters["variance_factor"] = r.statistics.variance_factor;
  state.counters["max_f_err_sigma"] = f_err;  // sanity: the solve converged to the truth
}
BENCHMARK(BM_Network)
    ->Apply(network_sizes)
    ->Args({2, 1000})  // target < 100 ms
    ->Args({2, 250})   // growth with epochs
    ->Args({2, 4000})
    ->Args({2, 16000})
    ->Args({4, 1000})  // growth with cameras
    ->Args({8, 1000})
    ->Args({8, 5000})
    ->Args({8, 20000});  // target < 3 s

// The same under the correlated PPK error model (ppk_error_model.hpp: white 0.35 of the fixes' sd,
// Gauss–Markov 0.8 / 1.4 cm, τ = 30 s over 5 Hz epochs): one GM state per epoch in the solve and in
// the covariance; its cost as a ratio to BM_Network at the same size, measured in the same run
// (docs/performance.md; targets 2 × 1,000 < 100 ms, 8 × 20,000 < 4 s).
void BM_NetworkCorrelated(benchmark::State& state) {
  NetworkOptions o;
  o.ppk_error.white_scale_h = o.ppk_error.white_scale_v = 0.35;
  o.ppk_error.gm_sd_h_m = 0.008, o.ppk_error.gm_sd_v_m = 0.014;
  o.ppk_error.tau_h_s = o.ppk_error.tau_v_s = 30;
  const TimedNetwork t = time_network_adjust(state, o);
  state.counters["observations"] = static_cast<double>(t.network.observations.size());
  state.counters["iterations"] = t.result.statistics.iterations;
}
BENCHMARK(BM_NetworkCorrelated)
    ->Apply(network_sizes)
    ->Args({2, 1000})  // target < 100 ms
    ->Args({8, 5000})
    ->Args({8, 20000});  // target < 4 s

// The PPK error model estimated from the mission (ppk_error_estimation.hpp; the calibrate stage's
// default): the restricted likelihood searched over the six parameters, then the final solve under
// the estimate; a ratio to BM_Network at the same size (docs/performance.md).
void BM_NetworkEstimatedModel(benchmark::State& state) {
  NetworkOptions o;
  o.estimate_ppk_error = true;
  const TimedNetwork t = time_network_adjust(state, o);
  if (t.result.ppk_estimate) {
    state.counters["evaluations"] = t.result.ppk_estimate->evaluations;
    // The synthetic fixes are white (1 cm): the likelihood-ratio test should keep the white model.
    state.counters["white"] = t.result.ppk_estimate->white;
    state.counters["likelihood_ratio"] = t.result.ppk_estimate->likelihood_ratio;
  }
  state.counters["iterations"] = t.result.statistics.iterations;
}
BENCHMARK(BM_NetworkEstimatedModel)
    ->Apply(network_sizes)
    ->Args({2, 1000})  // the solve's target < 100 ms
    ->Args({8, 5000})
    ->Args({8, 20000});  // the solve's target < 4 s

// The same on fixes whose error is correlated: the synthetic network's 1 cm white errors plus a
// Gauss–Markov process (0.8 / 1.4 cm, τ = 30 s, the realistic preset's) drawn over the 5 Hz epochs,
// each fix's covariance the total, as RTKLIB reports it. The estimate is then correlated and the
// final solve carries the states: the estimate's whole cost on the missions it is for.
void BM_NetworkEstimatedModelCorrelatedFixes(benchmark::State& state) {
  test::SyntheticNetwork n =
      test::synthetic_network(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), 11);
  std::mt19937_64 rng(29);
  std::normal_distribution<double> N01;
  const Eigen::Vector3d sd(0.008, 0.008, 0.014);
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < n.points.size(); ++k) {
    const double phi = k == 0 ? 0 : std::exp(-(n.points[k].time_s - n.points[k - 1].time_s) / 30.0);
    for (int a = 0; a < 3; ++a) g[a] = phi * g[a] + sd[a] * std::sqrt(1 - phi * phi) * N01(rng);
    n.points[k].prior_enu += g;
    n.points[k].prior_cov += Eigen::Matrix3d(sd.cwiseProduct(sd).asDiagonal());
  }
  NetworkOptions o;
  o.estimate_ppk_error = true;
  NetworkResult r;
  for (auto _ : state) {
    r = network_adjust(n.cameras, n.points, n.observations, o);
    benchmark::DoNotOptimize(r.statistics.chi2);
  }
  state.counters["peak_rss_MB"] = peak_rss_mb();
  if (r.ppk_estimate) {
    state.counters["evaluations"] = r.ppk_estimate->evaluations;
    state.counters["white"] = r.ppk_estimate->white;
    state.counters["tau_h_s"] = r.ppk_estimate->model.tau_h_s;
    state.counters["gm_sd_v_cm"] = 100 * r.ppk_estimate->model.gm_sd_v_m;
  }
  state.counters["iterations"] = r.statistics.iterations;
}
BENCHMARK(BM_NetworkEstimatedModelCorrelatedFixes)
    ->Apply(network_sizes)
    ->Args({2, 1000})  // target < 100 ms
    ->Args({8, 5000})
    ->Args({8, 20000});  // target < 4 s

// One evaluation of the restricted likelihood the estimate maximises (restricted_likelihood.hpp), on
// the synthetic network linearised at its start, under the correlated model of BM_NetworkCorrelated:
// the deviance alone (second argument 0) and with its gradient and average information (1), the
// estimate's two kinds of step (docs/performance.md).
void BM_RestrictedLikelihood(benchmark::State& state) {
  const test::SyntheticNetwork n = test::synthetic_network(static_cast<int>(state.range(0)), 1000, 11);
  const NetworkLayout layout = make_network_layout(n.cameras, n.points, n.observations);
  NetworkSelection selection{
      std::vector<char>(n.observations.size(), 1), std::vector<char>(n.points.size(), 1), {}, {}};
  const RemlMission mission = reml_mission(layout, starting_blocks(layout), selection, kEstimationEpochs);
  PpkErrorModel m;
  m.white_scale_h = m.white_scale_v = 0.35;
  m.gm_sd_h_m = 0.008, m.gm_sd_v_m = 0.014, m.tau_h_s = m.tau_v_s = 30;
  const LogParameters x = log_parameters_of(m, mission.cameras());
  RemlFactors factors;  // re-used, as the search re-uses its own
  for (auto _ : state) {
    factor_restricted_likelihood(mission, x, true, &factors);
    if (state.range(1) != 0) benchmark::DoNotOptimize(restricted_likelihood_derivatives(mission, factors));
    benchmark::DoNotOptimize(factors.deviance);
  }
}
BENCHMARK(BM_RestrictedLikelihood)
    ->ArgNames({"cameras", "derivatives"})
    ->Unit(benchmark::kMillisecond)
    ->ArgsProduct({{2, 8}, {0, 1}});

// The same with the datum floor the calibrate stage asks for (NetworkOptions::datum_floor_image_factor,
// one more joint covariance): its cost as a ratio to BM_Network at the same size, measured in the
// same run (docs/performance.md).
void BM_NetworkWithDatumFloor(benchmark::State& state) {
  const test::SyntheticNetwork n =
      test::synthetic_network(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), 11);
  NetworkOptions o;
  o.datum_floor_image_factor = kDatumFloorImageFactor;
  NetworkResult r;
  for (auto _ : state) {
    r = network_adjust(n.cameras, n.points, n.observations, o);
    benchmark::DoNotOptimize(r.datum_floor_covariance.data());
  }
  state.counters["floor_rows"] = static_cast<double>(r.datum_floor_covariance.rows());
}
BENCHMARK(BM_NetworkWithDatumFloor)->Apply(network_sizes)->Args({2, 1000})->Args({8, 5000});

}  // namespace
}  // namespace rangecal
