#pragma once
// Each CLI subcommand lives in its own pipeline/cli/<name>_command.cpp and registers itself on the
// CLI11 app through one of these functions (called from cli.cpp). A subcommand's callback throws
// rangecal::Error for user-caused failures; run_cli maps the error kind to the exit code.
#include <CLI/CLI.hpp>

namespace rangecal {

struct CliContext {
  bool quiet = false;    ///< --quiet: print only errors
  bool verbose = false;  ///< --verbose: print more detail
};

void add_gnss_command(CLI::App& app, const CliContext& ctx);
/// `rangecal align CONFIG` and `rangecal detect CONFIG` (pipeline/cli/stage_command.cpp).
void add_align_command(CLI::App& app, const CliContext& ctx);
void add_detect_command(CLI::App& app, const CliContext& ctx);
/// `rangecal calibrate CONFIG` (pipeline/cli/stage_command.cpp).
void add_calibrate_command(CLI::App& app, const CliContext& ctx);
/// `rangecal run CONFIG`: every stage (pipeline/cli/stage_command.cpp).
void add_run_command(CLI::App& app, const CliContext& ctx);

/// `rangecal simulate SCENARIO.json --out DIR` (docs/simulator.md; pipeline/cli/simulate_command.cpp).
void add_simulate_command(CLI::App& app, const CliContext& ctx);

/// `rangecal project --calibration CAL.json --points PTS.csv` (docs/cli.md;
/// pipeline/cli/project_command.cpp).
void add_project_command(CLI::App& app, const CliContext& ctx);

/// `rangecal compare-calibrations A.json B.json`: projection difference against the combined σ
/// (pipeline/cli/compare_command.cpp).
void add_compare_command(CLI::App& app, const CliContext& ctx);

/// `rangecal intersect CONFIG` and `rangecal intersect --calibration A.json --observations A.csv
/// ...` (docs/cli.md; pipeline/cli/intersect_command.cpp).
void add_intersect_command(CLI::App& app, const CliContext& ctx);

/// `rangecal report CONFIG`: report.html and summary.json (docs/outputs.md; pipeline/cli/report_command.cpp).
/// `rangecal trajectory CONFIG` (alias `track`): the target's trajectory from the cameras' target
/// tracks (docs/trajectory.md; pipeline/cli/stage_command.cpp).
void add_trajectory_command(CLI::App& app, const CliContext& ctx);
void add_report_command(CLI::App& app, const CliContext& ctx);

/// `rangecal montecarlo CONFIG` and `rangecal plan SCENARIO.json ...` (docs/accuracy_analysis.md;
/// pipeline/cli/montecarlo_command.cpp, pipeline/cli/plan_command.cpp).
void add_montecarlo_command(CLI::App& app, const CliContext& ctx);
void add_plan_command(CLI::App& app, const CliContext& ctx);

/// `rangecal inspect FILE… [--json]`: kind, header facts and UTC span of each input file, and the
/// overlap of their spans (pipeline/cli/inspect_command.cpp).
void add_inspect_command(CLI::App& app, const CliContext& ctx);

/// `rangecal demo [--out DIR]`: simulate the built-in scenario, run it, print Tables 1–4
/// (docs/cli.md; pipeline/cli/demo_command.cpp).
void add_demo_command(CLI::App& app, const CliContext& ctx);

}  // namespace rangecal
