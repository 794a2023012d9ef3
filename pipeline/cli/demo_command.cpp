// `rangecal demo [--out DIR] [--scenario FILE]` (docs/cli.md): simulates the built-in scenario
// mirroring seed 002's experiment, runs every stage on it and prints Tables 1–4 with the paper's
// figures beside ours, then the accuracy bars of docs/accuracy_analysis.md, Quality bars with pass/fail.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "pipeline/cli/commands.hpp"
#include "pipeline/cli/stage_command.hpp"
#include "pipeline/cli/stage_summary.hpp"
#include "pipeline/demo/demo.hpp"
#include "pipeline/demo/demo_bars.hpp"
#include "pipeline/demo/demo_scenario_text.hpp"
#include "pipeline/io/progress_bar.hpp"
#include "pipeline/simulate/scenario.hpp"

namespace rangecal {

void add_demo_command(CLI::App& app, const CliContext& ctx) {
  auto out_dir = std::make_shared<std::string>("demo-out");
  auto scenario_path = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand(
      "demo", "Simulate the built-in seed-002 scenario, run every stage on it and print Tables 1-4");
  sub->add_option("--out", *out_dir, "Folder for the simulated mission and its outputs (default demo-out)");
  sub->add_option("--scenario", *scenario_path, "Use this scenario (JSON) instead of the built-in one");
  sub->callback([out_dir, scenario_path, &ctx]() {
    set_progress_bars(!ctx.quiet && ::isatty(2));
    const Scenario scenario = scenario_path->empty()
                                  ? parse_scenario(demo_scenario_json(), "<built-in demo scenario>")
                                  : load_scenario(*scenario_path);
    const DemoRun run = simulate_and_run(scenario, *out_dir, [&](const std::string& line) {
      if (!ctx.quiet) std::cerr << "demo: " << line << "\n";
    });
    const DemoResults& r = run.results;
    if (!ctx.quiet) {
      for (const DemoCamera& c : r.cameras) std::cout << "\n" << format_demo_table1(c);
      std::cout << "\n" << format_demo_tables23(r.cameras);
      if (!r.intersections.empty()) std::cout << "\n" << format_demo_table4(r.intersections);
    }

    // docs/accuracy_analysis.md, Quality bars: measured against the simulated truth.
    const DemoBars bars = demo_accuracy_bars(r);
    std::cout << fmt::format(
        "\nAccuracy bars (docs/accuracy_analysis.md, Quality bars; a correct calibration passes all with "
        "probability >= {:.0f} %):\n",
        100 * (1 - kDemoBarsAlpha));
    for (const DemoBar& b : bars.bars) std::cout << b.line << "\n";
    for (const StageLog& log : run.logs) {
      const std::string line = log.stage == "report" ? flight_volume_line(log.counts) : "";
      if (!line.empty()) std::cout << "\nPredicted from the calibrations (report.html, Verdict):\n" << line;
    }
    std::cout << "\noutputs: " << run.config.output_dir << " (report.html, summary.json, run.json, ...)\n";
    if (!ctx.quiet)
      std::cout << "next:    rangecal montecarlo " << *out_dir
                << "/mission.json   (how far to trust these σ: bias and sd per parameter)\n"
                << "         rangecal plan config/examples/demo_scenario.json "
                   "config/examples/plan_mixed_routes.json   (routes compared before flying)\n";
    std::cout << std::flush;
    require_complete_outcome(run.config);  // a partial mission is exit 4 here as for `rangecal run`
    if (!bars.pass())
      throw_calibration_error(
          "demo", "an accuracy bar of docs/accuracy_analysis.md, Quality bars failed (see above)");
  });
}

}  // namespace rangecal
