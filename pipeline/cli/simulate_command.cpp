// `rangecal simulate SCENARIO.json --out DIR` (docs/cli.md, docs/simulator.md): renders a complete synthetic
// mission (RTKLIB .pos, attitude CSV, PNG frames with timestamps, pole survey and picks, mission config,
// truth.json) from a scenario; docs/simulator.md describes the scenario and the files.
#include <unistd.h>

#include <chrono>
#include <iostream>
#include <memory>
#include <string>

#include "config/number_format.hpp"
#include "pipeline/cli/commands.hpp"
#include "pipeline/io/progress_bar.hpp"
#include "pipeline/simulate/mission_simulator.hpp"
#include "pipeline/simulate/scenario.hpp"

namespace rangecal {

void add_simulate_command(CLI::App& app, const CliContext& ctx) {
  auto scenario_path = std::make_shared<std::string>();
  auto out_dir = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand("simulate", "Write a complete synthetic mission from a scenario (JSON)");
  sub->add_option("SCENARIO", *scenario_path, "Scenario (JSON), see docs/simulator.md")->required();
  sub->add_option("--out", *out_dir, "Output folder (created; files of the same names are replaced)")
      ->required();
  sub->callback([scenario_path, out_dir, &ctx]() {
    set_progress_bars(!ctx.quiet && ::isatty(2));
    const auto t0 = std::chrono::steady_clock::now();
    const Scenario scenario = load_scenario(*scenario_path);
    const SimMission mission = simulate_mission(scenario);
    const WrittenMission w = write_mission(mission, *out_dir);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (ctx.quiet) return;
    std::size_t in_view = 0, picks = 0;
    for (const SimCamera& c : mission.cameras) {
      for (const SimFrame& f : c.frames) in_view += f.in_view ? 1 : 0;
      picks += c.picks.size();
    }
    std::cout
        << fmt::format(
               "simulated {:.1f} s of flight: {} GNSS epochs, {} cameras, {} frames ({} with the lamp in "
               "view), {} poles, {} pole picks; {} files in {:.2f} s\n",
               mission.path.duration_s(), w.n_epochs, mission.cameras.size(), w.n_frames, in_view,
               mission.poles.size(), picks, w.n_files, secs)
        << "mission config: " << w.config_path << "\ntruth:          " << w.truth_path << "\n";
  });
}

}  // namespace rangecal
