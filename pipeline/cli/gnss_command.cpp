// `rangecal gnss CONFIG` (docs/gnss.md, docs/cli.md): runs the gnss stage alone, merges its section into
// run.json and prints a short summary (unless --quiet).
#include <iostream>
#include <memory>
#include <string>

#include "config/number_format.hpp"
#include "pipeline/cli/commands.hpp"
#include "pipeline/cli/stage_command.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/run_log.hpp"
#include "pipeline/mission/mission_config.hpp"
#include "pipeline/stages/mission_runner.hpp"

namespace rangecal {
namespace {

std::string row(const std::string& label, const std::string& value) {
  return fmt::format("  {:<28} {}\n", label, value);
}

std::string num(const nlohmann::json& v) {
  return v.is_null() ? "0" : v.dump();
}

/// The summary table from the stage's run.json counts.
std::string gnss_summary(const MissionConfig& cfg, const StageLog& log, bool verbose) {
  const nlohmann::json& c = log.counts;
  std::string s = "gnss stage: " + std::to_string(c["pos_files"].size()) + " .pos file(s)\n";
  for (const auto& f : c["pos_files"])
    s += "  " + f["path"].get<std::string>() + ": " + num(f["epochs"]) + " epochs, " +
         f["time_system"].get<std::string>() + " " + f["time_format"].get<std::string>() + ", " +
         f["position_format"].get<std::string>() + (f["velocity"].get<bool>() ? ", velocity" : "") + "\n";
  s += row("epochs read", num(c["epochs_read"]));
  s += row("epochs kept", num(c["epochs_kept"]));
  std::string byq;
  for (const auto& [q, n] : c["dropped_quality_by_q"].items())
    byq += (byq.empty() ? "" : ", ") + ("Q=" + q + ": " + n.dump());
  s += row("dropped: Q not accepted", num(c["dropped_quality"]) + (byq.empty() ? "" : "  (" + byq + ")"));
  s += row("dropped: sd > " + format_number("%.3f", cfg.gnss.max_sd_m) + " m", num(c["dropped_sd"]));
  if (!cfg.attitude_file.empty()) s += row("dropped: no attitude", num(c["dropped_no_attitude"]));
  s += row("gaps > " + format_number("%.3f", cfg.gnss.max_gap_s) + " s", num(c["gaps"]));
  if (verbose)
    for (const auto& g : c["gap_list"])
      s += "    " + g["from"].get<std::string>() + " .. " + g["to"].get<std::string>() + " (" +
           format_number("%.3f", g["duration_s"].get<double>()) + " s)\n";
  s += row("track", c["track_start"].get<std::string>() + " .. " + c["track_end"].get<std::string>() + " (" +
                        format_number("%.3f", c["track_span_s"].get<double>()) + " s)");
  const auto& la = c["lever_arm"];
  const std::string src = la["source"].get<std::string>();
  std::string lever;
  if (src == "body_frd") {
    lever = "body FRD (" + format_number("%.3f", la["body_frd_m"][0].get<double>()) + ", " +
            format_number("%.3f", la["body_frd_m"][1].get<double>()) + ", " +
            format_number("%.3f", la["body_frd_m"][2].get<double>()) + ") m with attitude";
  } else {
    lever = "vertical " + format_number("%.4f", la["vertical_m"].get<double>()) + " m";
    if (src == "total_station")
      lever += " +/- " + format_number("%.4f", la["vertical_sd_m"].get<double>()) + " m (total station, " +
               num(la["sessions"]) + " sessions)";
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
