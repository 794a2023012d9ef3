// Simulating the built-in demo scenario (config/examples/demo_scenario.json): the pure simulation
// (trajectory, epochs, attitude, frame list, picks) and the whole `rangecal simulate` (plus frame
// rendering, PNG encoding and every file written). Counters: frames written, GNSS epochs.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "pipeline/simulate/mission_simulator.hpp"
#include "pipeline/simulate/scenario.hpp"
#include "support/paths.hpp"

namespace {

std::string demo_path() {
  return (rangecal::test::source_dir() / "config" / "examples" / "demo_scenario.json").string();
}

void BM_SimulateDemoInMemory(benchmark::State& state) {
  const rangecal::Scenario s = rangecal::load_scenario(demo_path());
  std::size_t frames = 0, epochs = 0;
  for (auto _ : state) {
    const rangecal::SimMission m = rangecal::simulate_mission(s);
    frames = 0;
    for (const auto& c : m.cameras) frames += c.frames.size();
    epochs = m.epochs.size();
    benchmark::DoNotOptimize(frames);
  }
  state.counters["frames"] = static_cast<double>(frames);
  state.counters["epochs"] = static_cast<double>(epochs);
}
BENCHMARK(BM_SimulateDemoInMemory)->Unit(benchmark::kMillisecond);

void BM_SimulateDemoToFiles(benchmark::State& state) {
  const rangecal::Scenario s = rangecal::load_scenario(demo_path());
  const std::string out = rangecal::test::scratch_dir("bench_simulate_demo").string();
  rangecal::WrittenMission w;
  for (auto _ : state) w = rangecal::write_mission(rangecal::simulate_mission(s), out);
  state.counters["frames"] = static_cast<double>(w.n_frames);
  state.counters["files"] = static_cast<double>(w.n_files);
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(w.n_frames), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SimulateDemoToFiles)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
