// Benchmarks of optim/ (docs/accuracy_analysis.md, Quality bars): bundle adjustment on 1,000 points (target <
// 50 ms), SA-SSA with the paper-sized population, SSA on the SSA.md d = 30 benchmarks, LM-QN vs plain LM on a
// reduced analogue of seed 000's setup. Counters report iterations/evaluations/accuracy.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "optim/bundle/bundle_adjustment.hpp"
#include "optim/methods/tsai_sassa.hpp"
#include "optim/search/lm_qn.hpp"
#include "optim/search/sparrow_search.hpp"
#include "support/bundle_synthetic.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::VectorXd;

void BM_Bundle1000Points(benchmark::State& state) {
  // Seed-002-like camera, 1,000 points with 0.1 px and 1 cm noise, free f, k1, pose, Huber
  // + outlier pass + final least squares + covariance (the whole production path). Second
  // argument 1: the lamp moves (±4 m/s up or down, alternately), the camera clock is 2 ms late
  // and clock_offset is free too.
  const bool clock = state.range(1) != 0;
  const Camera truth = test::narrow_fov_camera();
  const auto pts = test::synthetic_points(truth, static_cast<int>(state.range(0)), 3);
  std::mt19937_64 rng(4);
  std::normal_distribution<double> N01;
  std::vector<BundleObservation> obs(pts.world.size());
  for (std::size_t i = 0; i < obs.size(); ++i) {
    obs[i].world = pts.world[i] + 0.01 * Vector3d(N01(rng), N01(rng), N01(rng));
    obs[i].pixel = pts.pixel[i] + 0.1 * Vector2d(N01(rng), N01(rng));
    obs[i].world_cov = Matrix3d::Identity() * 1e-4;
    if (clock) {
      obs[i].velocity = Vector3d(0, 0, i % 2 ? 4.0 : -4.0);
      obs[i].world += obs[i].velocity * 0.002;
    }
  }
  BundleOptions opt;
  if (clock) opt.free.push_back("clock_offset");
  Camera start = truth;
  start.intr.f_mm *= 1.02;
  start.intr.dist.k1 = 0;
  const Vector3d C = truth.pose.center() + Vector3d(0.3, -0.2, 0.35);
  start.pose.R =
      Eigen::AngleAxisd(0.005, Vector3d(1, -1, 0.5).normalized()).toRotationMatrix() * truth.pose.R;
  start.pose.T = -start.pose.R * C;
  BundleResult r;
  for (auto _ : state) {
    r = bundle_adjust(start, obs, opt);
    benchmark::DoNotOptimize(r.chi2);
  }
  state.counters["iterations"] = r.iterations;
  state.counters["f_err_mm"] = r.calibration.camera.intr.f_mm - truth.intr.f_mm;
  state.counters["sigma_f_mm"] = r.calibration.sigma(CameraParameter::f);
  if (clock) state.counters["clock_err_ms"] = (r.calibration.clock_offset_s - 0.002) * 1e3;
}
BENCHMARK(BM_Bundle1000Points)
    ->Args({1000, 0})
    ->Args({100, 0})
    ->Args({1000, 1})
    ->Unit(benchmark::kMillisecond);

void BM_SsaBenchmarksD30(benchmark::State& state) {
  // SSA.md's faithfulness size: d = 30, n = 100, M = 1000 (120,100 evaluations), Rastrigin.
  const int d = 30;
  SparrowOptions o;
  o.population = 100;
  o.max_iterations = 1000;
  auto rastrigin = [](const VectorXd& x) {
    double s = 10.0 * x.size();
    for (Eigen::Index i = 0; i < x.size(); ++i) s += x[i] * x[i] - 10.0 * std::cos(2 * M_PI * x[i]);
    return s;
  };
  SparrowResult r;
  for (auto _ : state) {
    r = sparrow_search(rastrigin, VectorXd::Constant(d, -5.12), VectorXd::Constant(d, 5.12), o);
    benchmark::DoNotOptimize(r.f);
  }
  state.counters["evaluations"] = static_cast<double>(r.evaluations);
  state.counters["f"] = r.f;
}
BENCHMARK(BM_SsaBenchmarksD30)->Unit(benchmark::kMillisecond);

void BM_TsaiSassaPaperSized(benchmark::State& state) {
  // tsai_sassa on the range scene (3 ascents × 40 lamp points + 4 poles, 0.1 px noise) with the
  // population the paper implies (SSA's original setting n = 100, M = 1000; SA adds n per
  // iteration → 220,100 evaluations), then the LM polish. Arg 0: CI-sized n = 30, M = 200.
  const Camera truth = test::range_camera(-2e-5);
  TsaiSensor sensor;
  sensor.width_px = 1280, sensor.height_px = 800, sensor.dx_mm = sensor.dy_mm = 0.02;
  sensor.u0_px = truth.intr.u0_px, sensor.v0_px = truth.intr.v0_px;
  const auto pts = test::observe(truth, test::range_world_points(truth), 0.1, 0.0, 5);
  TsaiSassaOptions o;
  if (state.range(0) == 1) o.search.population = 100, o.search.max_iterations = 1000;
  TsaiSassaResult r;
  for (auto _ : state) {
    r = tsai_sassa_calibrate(pts, sensor, o);
    benchmark::DoNotOptimize(r.search.f);
  }
  state.counters["evaluations"] = static_cast<double>(r.search.search.evaluations);
  state.counters["z_norm"] = r.search.z_norm;
  state.counters["search_rms_px"] = r.search_rms_px;
  state.counters["polished_rms_px"] = r.calibration.reprojection.rms_px;
  state.counters["f_err_mm"] = r.camera.intr.f_mm - truth.intr.f_mm;
}
BENCHMARK(BM_TsaiSassaPaperSized)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// Reduced analogue of seed 000's setup (72 images from 6 stations, thousands of wall targets, 150 mm
// lens): one station, 150 3-D targets, 150 mm-class narrow lens on a 8208×6280, 5.3 µm sensor,
// 0.3 px noise, all seed 000 unknowns of one image: f, xp, yp, k1, k2, k3, p1, p2, a1, a2, pose
// (16), from a DLT-quality start, numeric Jacobian, parameters scaled to unit magnitude.
struct Seed000Problem {
  Camera truth, start;
  std::vector<Vector3d> X;
  std::vector<Vector2d> uv;
  VectorXd scale;
  Seed000Problem() {
    Camera& t = truth;
    t.intr.width_px = 8208, t.intr.height_px = 6280, t.intr.dx_mm = t.intr.dy_mm = 0.0053;
    t.intr.f_mm = 150, t.intr.u0_px = 4110, t.intr.v0_px = 3135;
    t.intr.dist = {2e-6, -3e-10, 1e-14, 4e-6, -2e-6, 5e-5, -3e-5};
    const Vector3d C(0, 0, 1.5);
    t.pose.R = test::look_at_pose(C, Vector3d(5, 40, 6)).R;
    t.pose.T = -t.pose.R * C;
    const auto pts = test::synthetic_points(t, 150, 11, 30, 55);
    std::mt19937_64 rng(12);
    std::normal_distribution<double> N01;
    X = pts.world;
    for (const auto& p : pts.pixel) uv.push_back(p + 0.3 * Vector2d(N01(rng), N01(rng)));
    start = t;
    start.intr.f_mm *= 1.01;
    start.intr.u0_px = 4104, start.intr.v0_px = 3140;
    start.intr.dist = Distortion{};
    start.pose.R = Eigen::AngleAxisd(0.003, Vector3d(1, 2, 3).normalized()).toRotationMatrix() * t.pose.R;
    start.pose.T = -start.pose.R * (C + Vector3d(0.05, -0.1, 0.05));
    scale.resize(16);
    scale << 1, 10, 10, 1e-6, 1e-10, 1e-14, 1e-6, 1e-6, 1e-5, 1e-5, 1e-3, 1e-3, 1e-3, 0.1, 0.1, 0.1;
  }
  bool residual(const VectorXd& x, VectorXd* r) const {
    const VectorXd th = x.cwiseProduct(scale);
    Camera c = start;
    c.intr.f_mm += th[0], c.intr.u0_px += th[1], c.intr.v0_px += th[2];
    auto d = start.intr.dist.as_array();
    for (int k = 0; k < 7; ++k) d[k] += th[3 + k];
    c.intr.dist = Distortion::from_array(d.data());
    const Vector3d w = th.segment<3>(10);
    const Matrix3d dR =
        w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Matrix3d::Identity();
    c.pose.R = dR * start.pose.R;
    c.pose.T = -c.pose.R * (start.pose.center() + th.segment<3>(13));
    return test::reprojection_residuals(c, X, uv, r);
  }
};

void BM_LmQnVsLmSeed000Analogue(benchmark::State& state) {
  const Seed000Problem P;
  const ResidualFunction r = [&](const VectorXd& x, VectorXd* res) { return P.residual(x, res); };
  LmQnOptions o;
  o.allow_qn = state.range(0) == 1;
  LmQnResult res;
  for (auto _ : state) {
    res = lm_qn_minimise(r, nullptr, VectorXd::Zero(16), o);
    benchmark::DoNotOptimize(res.F);
  }
  state.SetLabel(o.allow_qn ? "LM-QN" : "LM");
  state.counters["iterations"] = res.iterations;
  state.counters["lm_steps"] = res.lm_steps;
  state.counters["qn_steps"] = res.qn_steps;
  state.counters["r_evals"] = static_cast<double>(res.residual_evaluations);
  state.counters["rms_px"] = std::sqrt(2 * res.F / static_cast<double>(res.residual.size()));
  state.counters["converged"] = res.converged;
}
BENCHMARK(BM_LmQnVsLmSeed000Analogue)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rangecal
