// `rangecal gnss CONFIG` (docs/gnss.md, docs/cli.md): runs the gnss stage alone, merges its section into
// run.json and prints a short summary (unless --quiet).
#include <iostream>
#include <memory>
#include <string>

#include "config/number_format.hpp"
#include "pipeline/cli/commands.hpp"
#include "pipeline/cli/stage_command.hpp"
#include "pipeline/io/gnss_record.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/run_log.hpp"
#include "pipeline/mission/mission_config.hpp"
#include "pipeline/stages/mission_runner.hpp"

namespace rangecal {
namespace {

std::string row(const std::string& label, const std::string& value) {
  return fmt::format("  {:<28} {}\n", label, value);
}

/// The summary table from the stage's run.json record.
std::string gnss_summary(const MissionConfig& cfg, const StageLog& log, bool verbose) {
  const GnssRecord c = parse_gnss_record(log.counts, "run.json", "stages.gnss.counts");
  std::string s = "gnss stage: " + std::to_string(c.pos_files.size()) + " .pos file(s)\n";
  for (const PosFileRecord& f : c.pos_files)
    s += "  " + f.path + ": " + std::to_string(f.epochs) + " epochs, " + f.time_system + " " + f.time_format +
         ", " + f.position_format + (f.velocity ? ", velocity" : "") + "\n";
  s += row("epochs read", std::to_string(c.epochs_read));
  s += row("epochs kept", std::to_string(c.epochs_kept));
  std::string byq;
  for (const auto& [q, n] : c.dropped_quality_by_q)
    byq += (byq.empty() ? "" : ", ") + ("Q=" + std::to_string(q) + ": " + std::to_string(n));
  s += row("dropped: Q not accepted",
           std::to_string(c.dropped_quality) + (byq.empty() ? "" : "  (" + byq + ")"));
  s += row("dropped: sd > " + format_number("%.3f", cfg.gnss.max_sd_m) + " m", std::to_string(c.dropped_sd));
  if (!cfg.attitude_file.empty()) s += row("dropped: no attitude", std::to_string(c.dropped_no_attitude));
  s += row("gaps > " + format_number("%.3f", cfg.gnss.max_gap_s) + " s", std::to_string(c.gap_list.size()));
  if (verbose)
    for (const GapRecord& g : c.gap_list)
      s += "    " + g.from + " .. " + g.to + " (" + format_number("%.3f", g.duration_s) + " s)\n";
  s += row("track",
           c.track_start + " .. " + c.track_end + " (" + format_number("%.3f", c.track_span_s) + " s)");
  const LeverArmRecord& la = c.lever_arm;
  std::string lever;
  if (la.source == "body_frd") {
    lever = "body FRD (" + format_number("%.3f", la.body_frd_m[0]) + ", " +
            format_number("%.3f", la.body_frd_m[1]) + ", " + format_number("%.3f", la.body_frd_m[2]) +
            ") m with attitude";
  } else {
    lever = "vertical " + format_number("%.4f", la.vertical_m) + " m";
    if (la.source == "total_station")
      lever += " +/- " + format_number("%.4f", la.vertical_sd_m) + " m (total station, " +
               std::to_string(la.sessions) + " sessions)";
  }
  s += row("lever arm", lever);
  s += row("output", lamp_track_path(cfg));
  return s;
}

}  // namespace

void add_gnss_command(CLI::App& app, const CliContext& ctx) {
  auto config_path = std::make_shared<std::string>();
  CLI::App* sub =
      app.add_subcommand("gnss", "PPK .pos files -> lamp track in site ENU (gnss/lamp_track.csv)");
  sub->add_option("CONFIG", *config_path, "Mission config (JSON)")->required();
  sub->callback([config_path, &ctx]() {
    const MissionConfig cfg = load_mission_config(*config_path);
    const StageLog log = run_stage("gnss", cfg);
    if (!ctx.quiet) {
      std::cout << gnss_summary(cfg, log, ctx.verbose) << std::flush;
      for (const std::string& w : log.warnings) std::cerr << "warning: " << w << "\n";
    }
    require_complete_outcome(cfg);
  });
}

}  // namespace rangecal
