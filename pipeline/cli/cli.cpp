#include "pipeline/cli/cli.hpp"

#include <glog/logging.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <exception>
#include <iostream>
#include <new>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <string>
#include <vector>

#include "config/error.hpp"
#include "config/json_view.hpp"
#include "config/text_encoding.hpp"
#include "pipeline/cli/commands.hpp"

namespace rangecal {

namespace {

// Ceres logs through glog and OpenCV through its own logger: neither may chatter on a user's
// console (nor write log files to /tmp). rangecal's own messages say what matters.
void silence_library_logging(const char* argv0) {
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = google::GLOG_ERROR;
  if (!google::IsGoogleLoggingInitialized()) google::InitGoogleLogging(argv0);
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
}

// The first word that is not an option must name a command. CLI11 would only say "The following
// arguments were not expected"; a range engineer typing `rangecal calibarte` wants the nearest.
std::string unknown_command_message(const CLI::App& app, int argc, char** argv) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    names.push_back(sub->get_name());
    for (const std::string& alias : sub->get_aliases()) names.push_back(alias);
  }
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') continue;
    if (std::find(names.begin(), names.end(), word) != names.end()) return "";
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    return "unknown command '" + printable_text(word) + "'" + did_you_mean(word, names) +
           "; commands: " + list + " (rangecal --help)";
  }
  return "";
}

}  // namespace

int run_cli(int argc, char** argv) {
  silence_library_logging(argc > 0 ? argv[0] : "rangecal");
  CLI::App app{"rangecal — high-speed camera calibration from a PPK-positioned UAV lamp"};
  app.require_subcommand(1);
  // -q/-v may also follow the command (`rangecal run -q mission.json`): subcommands created after
  // this pass options they do not know up to the top level.
  app.fallthrough();
  app.set_version_flag("--version", std::string(RANGECAL_VERSION));
  CliContext ctx;
  app.add_flag("--quiet,-q", ctx.quiet, "Print only errors");
  app.add_flag("--verbose,-v", ctx.verbose, "Print more detail");

  add_run_command(app, ctx);
  add_gnss_command(app, ctx);
  add_align_command(app, ctx);
  add_detect_command(app, ctx);
  add_calibrate_command(app, ctx);
  add_simulate_command(app, ctx);
  add_project_command(app, ctx);
  add_compare_command(app, ctx);
  add_intersect_command(app, ctx);
  add_trajectory_command(app, ctx);
  add_report_command(app, ctx);
  add_montecarlo_command(app, ctx);
  add_plan_command(app, ctx);
  add_demo_command(app, ctx);
  add_inspect_command(app, ctx);

  if (const std::string message = unknown_command_message(app, argc, argv); !message.empty()) {
    std::cerr << "rangecal: error: " << message << "\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  } catch (const Error& e) {
    std::cerr << "rangecal: error: " << e.what() << "\n";
    return e.exit_code();
  } catch (const std::bad_alloc&) {
    std::cerr << "rangecal: error: out of memory (an input asks for more than this machine has)\n";
    return 3;
  } catch (const cv::Exception& e) {
    // Readers check sizes and files before OpenCV sees them; what still fails there is input data.
    std::cerr << "rangecal: error: image library: " << printable_text(e.what()) << "\n";
    return 3;
  } catch (const nlohmann::json::exception& e) {
    std::cerr << "rangecal: error: JSON: " << printable_text(e.what()) << "\n";
    return 3;
  } catch (const std::exception& e) {
    // Not a user-caused failure we anticipated: still a clean message and a non-zero exit.
    std::cerr << "rangecal: internal error: " << printable_text(e.what()) << "\n";
    return 1;
  }
  return 0;
}

}  // namespace rangecal
