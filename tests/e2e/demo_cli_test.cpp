// The demo scenario end to end (docs/accuracy_analysis.md, Quality bars quality bars): simulate seed 002's
// experiment, run every stage on the written files, and hold the results against the simulated truth. Then
// prove the bar can fail: the same mission with its lever arm ignored, or its GPST read as UTC, misses it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "gnss/time/utc_time.hpp"
#include "pipeline/demo/demo.hpp"
#include "pipeline/demo/demo_scenario_text.hpp"
#include "pipeline/simulate/scenario.hpp"
#include "pipeline/stages/mission_runner.hpp"
#include "support/paths.hpp"
#include "support/simulated_mission.hpp"

namespace rangecal {
namespace {
namespace fs = std::filesystem;

// One simulation shared by the tests of this file (it takes most of the time).
const test::SimulatedRun& demo() {
  static const test::SimulatedRun f = test::simulate_and_run_in_scratch(
      parse_scenario(demo_scenario_json(), "<built-in demo scenario>"), "demo");
  return f;
}

TEST(Demo, KillingARunMidwayLeavesNoPartialOutputFiles) {
  const test::SimulatedRun& d = demo();
  int files_seen = 0;
  for (const int delay_ms : {300, 900, 1800}) {
    const fs::path dst = d.dir / ("killed_" + std::to_string(delay_ms));
    test::copy_mission_inputs(d.dir / "mission", dst);
    const std::string bin = test::rangecal_binary().string(), cfg = (dst / "mission.json").string();
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      if (!std::freopen("/dev/null", "w", stdout) || !std::freopen("/dev/null", "w", stderr)) ::_exit(126);
      ::execl(bin.c_str(), "rangecal", "-q", "run", cfg.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::usleep(delay_ms * 1000);
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    const fs::path out = dst / "out";
    if (!fs::exists(out)) continue;
    for (const auto& e : fs::recursive_directory_iterator(out)) {
      if (!e.is_regular_file()) continue;
      ++files_seen;
      const std::string name = e.path().filename().string(), text = test::read_text(e.path());
      EXPECT_EQ(name.find(".tmp."), std::string::npos) << "temporary file left: " << e.path();
      EXPECT_FALSE(text.empty()) << e.path();
      EXPECT_EQ(text.back(), '\n') << "truncated: " << e.path();
      const std::string ext = e.path().extension().string();
      if (ext == ".csv") {
        EXPECT_NO_THROW(parse_csv(text, e.path().string())) << e.path();
      } else if (ext == ".json") {
        EXPECT_TRUE(nlohmann::json::accept(text)) << e.path();
      } else if (ext == ".html") {
        EXPECT_NE(text.find("</html>"), std::string::npos) << e.path();
      }
    }
  }
  EXPECT_GT(files_seen, 0) << "the runs were killed before writing anything: nothing was checked";
}

}  // namespace
}  // namespace rangecal
