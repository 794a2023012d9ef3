// Whole-pipeline benchmarks (issues 4 and 5): the demo end to end with its per-stage wall times
// (target < 60 s on 2 cores), and align + detect over 1,000 real PNG frames read from disk
// (16-bit 1280×800, decoding included) with 1 and 2 threads. The missions are simulated into a
// temp folder at start (not timed).
#include <benchmark/benchmark.h>

#include <filesystem>

#include "pipeline/demo/demo.hpp"
#include "pipeline/demo/demo_scenario_text.hpp"
#include "pipeline/mission/mission_config.hpp"
#include "pipeline/simulate/scenario.hpp"
#include "pipeline/stages/align_stage.hpp"
#include "pipeline/stages/detect_stage.hpp"
#include "pipeline/stages/gnss_stage.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

void BM_DemoEndToEnd(benchmark::State& state) {
  const auto dir = test::scratch_dir("bench_demo");
  const Scenario s = parse_scenario(demo_scenario_json(), "<built-in demo scenario>");
  DemoRun run;
  for (auto _ : state) run = simulate_and_run(s, (dir / "mission").string());
  for (const StageLog& l : run.logs) state.counters[l.stage + "_s"] = l.wall_time_s;
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_DemoEndToEnd)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

// One camera of the demo with 50 Hz PPK and every 10th frame of 500 fps exported, so that every
// epoch of the ~30 s flight has its frame: ~1,500 aligned frames, about half with the lamp.
const MissionConfig& thousand_frame_mission() {
  static const MissionConfig cfg = [] {
    const auto dir = test::scratch_dir("bench_align_detect");
    Scenario s = parse_scenario(demo_scenario_json(), "<built-in demo scenario>");
    s.cameras.resize(1);
    s.cameras[0].export_step = 10;
    s.gnss.rate_hz = 50;
    write_mission(simulate_mission(s), dir.string());
    MissionConfig c = load_mission_config((dir / "mission.json").string());
    update_run_log(c, run_gnss_stage(c));
    return c;
  }();
  return cfg;
}

void BM_AlignDetect1500Frames(benchmark::State& state) {
  MissionConfig cfg = thousand_frame_mission();
  cfg.detect.threads = static_cast<int>(state.range(0));
  long frames = 0;
  for (auto _ : state) {
    run_align_stage(cfg);
    const StageLog d = run_detect_stage(cfg);
    frames = d.counts.value("/cam1/frames_examined"_json_pointer, 0L);
  }
  state.counters["frames"] = static_cast<double>(frames);
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_AlignDetect1500Frames)->Arg(1)->Arg(2)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

}  // namespace
}  // namespace rangecal
