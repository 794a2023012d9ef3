#pragma once
// `rangecal STAGE CONFIG` for the stages that follow one pattern: load the config, run the stage
// (pipeline/stages/mission_runner.hpp: timed, merged into run.json), print its counts and
// warnings (unless --quiet).
#include <CLI/CLI.hpp>
#include <string>

#include "pipeline/cli/commands.hpp"
#include "pipeline/io/run_log.hpp"

namespace rangecal {

/// Adds `rangecal <stage> CONFIG`; `stage` names one of mission_stages().
void add_stage_command(CLI::App& app, const CliContext& ctx, const std::string& stage,
                       const std::string& description);

}  // namespace rangecal
