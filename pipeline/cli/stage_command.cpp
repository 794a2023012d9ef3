#include "pipeline/cli/stage_command.hpp"

#include <unistd.h>

#include <iostream>
#include <memory>

#include "config/error.hpp"
#include "pipeline/cli/stage_summary.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/progress_bar.hpp"
#include "pipeline/io/run_outcome.hpp"
#include "pipeline/io/stage_outputs.hpp"
#include "pipeline/stages/mission_runner.hpp"
#include "pipeline/stages/trajectory_stage.hpp"

namespace rangecal {

void require_complete_outcome(const MissionConfig& cfg) {
  const RunOutcome outcome = read_run_outcome(cfg);
  if (outcome.status == "complete") return;
  if (outcome.status == "degraded") {
    // Complete, exit 0; the batch reads run.json's outcome, the user this line.
    std::cerr << "rangecal: warning: " << mission_output(cfg, kRunJson)
              << ": the mission is degraded (look before trusting it): " << outcome_reasons_text(outcome)
              << "\n";
    return;
  }
  const ErrorKind kind = outcome.exit_code == 2 || outcome.exit_code == 3
                             ? static_cast<ErrorKind>(outcome.exit_code)
                             : ErrorKind::calibration;
  throw Error(kind, mission_output(cfg, kRunJson), 0, "outcome",
              outcome.status == "partial"
                  ? "the mission is partial (its outputs are kept and marked so in run.json and "
                    "summary.json): " +
                        outcome_reasons_text(outcome)
                  : "an earlier stage's failure is still recorded: " + outcome_reasons_text(outcome));
}

void add_stage_command(CLI::App& app, const CliContext& ctx, const std::string& stage,
                       const std::string& description) {
  CLI::App* sub = app.add_subcommand(stage, description);
  auto config = std::make_shared<std::string>();
  sub->add_option("CONFIG", *config, "Mission config (JSON)")->required();
  sub->callback([&ctx, config, stage] {
    const MissionConfig cfg = load_mission_config(*config);
    set_progress_bars(!ctx.quiet && ::isatty(2));
    const StageLog log = run_stage(stage, cfg);
    if (!ctx.quiet) std::cout << stage_summary(log, ctx.verbose) << std::flush;
    require_complete_outcome(cfg);
  });
}

void add_align_command(CLI::App& app, const CliContext& ctx) {
  add_stage_command(app, ctx, "align",
                    "Pick each camera's frames nearest the lamp-track epochs and interpolate the lamp "
                    "position to their UTC (writes <cam>/aligned.csv)");
}

void add_detect_command(CLI::App& app, const CliContext& ctx) {
  add_stage_command(app, ctx, "detect",
                    "Find the lamp in the aligned frames (writes <cam>/detections.csv and "
                    "<cam>/correspondences.csv)");
}

void add_calibrate_command(CLI::App& app, const CliContext& ctx) {
  add_stage_command(
      app, ctx, "calibrate",
      "Calibrate each camera from <cam>/correspondences.csv (writes calibration.json, "
      "camera_opencv.yml, dlt_coefficients.csv, argus_profile.txt, residuals.csv, methods.csv)");
}

void add_trajectory_command(CLI::App& app, const CliContext& ctx) {
  CLI::App* sub = app.add_subcommand(
      "trajectory",
      "Triangulate the target of the cameras' target tracks at every output instant, with σ from the labels, "
      "their timing and the calibrations (writes trajectory.csv)");
  sub->alias("track");
  auto config = std::make_shared<std::string>();
  sub->add_option("CONFIG", *config, "Mission config (JSON)")->required();
  sub->callback([&ctx, config] {
    const MissionConfig cfg = load_mission_config(*config);
    require_trajectory_inputs(cfg);  // asked for this stage alone: nothing to do is an error
    const StageLog log = run_stage("trajectory", cfg);
    if (!ctx.quiet) std::cout << stage_summary(log, ctx.verbose) << std::flush;
    require_complete_outcome(cfg);
  });
}

void add_run_command(CLI::App& app, const CliContext& ctx) {
  std::string stages;
  for (const std::string& name : mission_stage_names()) stages += (stages.empty() ? "" : ", ") + name;
  CLI::App* sub = app.add_subcommand("run", "Run every stage: " + stages);
  auto config = std::make_shared<std::string>();
  sub->add_option("CONFIG", *config, "Mission config (JSON)")->required();
  sub->callback([&ctx, config] {
    const MissionConfig cfg = load_mission_config(*config);
    // Progress on stderr only when a person is watching it.
    const bool progress = !ctx.quiet && ::isatty(2);
    set_progress_bars(progress);
    const std::size_t n = mission_stages().size();
    std::size_t done = 0;
    run_mission(cfg, [&](const StageLog& log) {
      ++done;
      if (progress) std::cerr << "[" << done << "/" << n << "] " << log.stage << " done\n";
      if (!ctx.quiet) std::cout << stage_summary(log, ctx.verbose);
    });
    std::cout << std::flush;
    require_complete_outcome(cfg);
  });
}

}  // namespace rangecal
