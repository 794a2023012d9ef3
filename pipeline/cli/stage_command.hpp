#pragma once
// `rangecal STAGE CONFIG` for the stages that follow one pattern: load the config, run the stage,
// merge its log into run.json, print its counts and warnings (unless --quiet).
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "config/mission_config.hpp"
#include "pipeline/cli/commands.hpp"
#include "pipeline/io/run_log.hpp"

namespace rangecal {

using StageFunction = std::function<StageLog(const MissionConfig&)>;

void add_stage_command(CLI::App& app, const CliContext& ctx, const std::string& name,
                       const std::string& description, StageFunction run);

/// Prints a stage log as an indented summary to stdout (counts as compact JSON lines per key).
void print_stage_summary(const StageLog& log, bool verbose);

}  // namespace rangecal
