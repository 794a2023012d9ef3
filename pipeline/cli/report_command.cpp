// `rangecal report CONFIG` (docs/outputs.md, docs/cli.md): writes report.html and summary.json from the files
// the earlier stages left in the output folder, merges its log into run.json.
#include "pipeline/cli/commands.hpp"
#include "pipeline/cli/stage_command.hpp"

namespace rangecal {

void add_report_command(CLI::App& app, const CliContext& ctx) {
  add_stage_command(app, ctx, "report",
                    "Write report.html (tables and inline SVG plots) and summary.json from the output "
                    "folder");
}

}  // namespace rangecal
