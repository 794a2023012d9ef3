#pragma once
// `rangecal STAGE CONFIG` for the stages that follow one pattern: load the config, run the stage
// (pipeline/stages/mission_runner.hpp: timed, merged into run.json), print its counts and
// warnings (unless --quiet).
#include <CLI/CLI.hpp>
#include <string>

#include "pipeline/cli/commands.hpp"
#include "pipeline/io/run_log.hpp"
#include "pipeline/mission/mission_config.hpp"

namespace rangecal {

/// Adds `rangecal <stage> CONFIG`; `stage` names one of mission_stages().
void add_stage_command(CLI::App& app, const CliContext& ctx, const std::string& stage,
                       const std::string& description);

/// After a mission command whose stages all finished: throws unless run.json's outcome
/// (pipeline/io/run_outcome.hpp) is complete — exit 4 for a partial mission, naming run.json, the
/// field `outcome` and the reasons; a stage's exit code when an earlier stage's failure is still
/// recorded — so that exit 0 always means a complete mission (docs/reliability.md "Run outcome").
void require_complete_outcome(const MissionConfig& cfg);

}  // namespace rangecal
