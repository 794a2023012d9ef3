// Benchmarks of the accuracy analysis (docs/accuracy_analysis.md): `montecarlo` trials
// (two demo cameras re-calibrated per trial, 11 check poles triangulated) on 1 and 2 threads, and
// `plan` on the shipped candidate scenarios (simulate the trajectory, Cramér–Rao bound of each
// camera for two free sets, poles).
#include <benchmark/benchmark.h>

#include "pipeline/analysis/monte_carlo.hpp"
#include "pipeline/analysis/route_plan.hpp"
#include "pipeline/simulate/scenario.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

Scenario example(const char* name) {
  return load_scenario((test::source_dir() / "config/examples" / name).string());
}

/// The demo's two cameras calibrated from their planned observations (lamp points and control
/// poles), as montecarlo re-runs a finished mission.
struct McSetup {
  std::vector<MonteCarloCamera> cameras;
  std::vector<MonteCarloPole> poles;
};

McSetup demo_setup(bool clock_offset) {
  const Scenario s = example("seed002_scenario.json");
  McSetup m;
  for (std::size_t c = 0; c < s.cameras.size(); ++c) {
    MonteCarloCamera mc;
    const Camera& t = s.cameras[c].camera;
    mc.problem.camera_id = s.cameras[c].id;
    mc.problem.sensor = {t.intr.width_px, t.intr.height_px, t.intr.dx_mm, t.intr.dy_mm};
    mc.problem.nominal_focal_mm = 135;
    mc.problem.free = {"f", "k1", "pose"};
    if (clock_offset) mc.problem.free.push_back("clock_offset");
    mc.problem.observations = planned_observations(s, c);
    mc.reference = calibrate_camera("bundle", mc.problem);
    m.cameras.push_back(mc);
  }
  for (const ScenarioPole& p : s.poles)
    if (p.role == "check") m.poles.push_back({p.id, p.enu_m, {0, 1}});
  return m;
}

void BM_MonteCarlo(benchmark::State& state) {
  const McSetup m = demo_setup(state.range(1) != 0);
  MonteCarloOptions o;
  o.trials = 200;
  o.threads = static_cast<int>(state.range(0));
  o.pick_sigma_px = 0.2;
  MonteCarloResult r;
  for (auto _ : state) {
    r = run_monte_carlo(m.cameras, m.poles, o);
    benchmark::DoNotOptimize(r.trials);
  }
  state.counters["trials"] = o.trials;
  state.counters["sd_ratio_f_cam1"] =
      r.cameras[0].parameters[0].sd_mc / r.cameras[0].parameters[0].sd_predicted;
}
// Args: threads, clock_offset free.
BENCHMARK(BM_MonteCarlo)
    ->Args({1, 0})
    ->Args({2, 0})
    ->Args({2, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_Plan(benchmark::State& state) {
  const Scenario s = example(state.range(0) ? "plan_mixed_routes.json" : "seed002_scenario.json");
  RoutePlanAnalysis a;
  for (auto _ : state) {
    a = analyse_route_plan(s, "candidate");
    benchmark::DoNotOptimize(a.free_sets.size());
  }
  state.counters["points_cam1"] = a.free_sets[0].cameras[0].n_points;
}
// Arg: 0 the demo's three ascents, 1 the mixed routes.
BENCHMARK(BM_Plan)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rangecal
