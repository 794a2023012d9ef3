// `rangecal simulate` (docs/cli.md): writes a mission from a scenario file and refuses a malformed
// one with exit code and field (the simulator's own results: tests/unit/pipeline/
// mission_simulator_test.cpp).
#include "pipeline/simulate/mission_simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "pipeline/mission/mission_config.hpp"
#include "support/paths.hpp"
#include "support/tiny_scenario.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

TEST(MissionSimulator, CliSimulateWritesAndRejects) {
  const fs::path dir = test::scratch_dir("sim_cli");
  test::write_text(dir / "tiny.json", test::tiny_scenario().dump(2));
  const auto ok =
      test::run_cli("simulate '" + (dir / "tiny.json").string() + "' --out '" + (dir / "out").string() + "'");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("71 frames"), std::string::npos) << ok.out;
  EXPECT_TRUE(fs::is_regular_file(dir / "out" / "mission.json"));
  json bad = test::tiny_scenario();
  bad["routes"][0]["speed"] = 2;
  test::write_text(dir / "bad.json", bad.dump(2));
  const auto err =
      test::run_cli("simulate '" + (dir / "bad.json").string() + "' --out '" + (dir / "out2").string() + "'");
  EXPECT_EQ(err.exit_code, 2);
  EXPECT_NE(err.err.find("routes[0].speed"), std::string::npos) << err.err;
  EXPECT_FALSE(fs::exists(dir / "out2"));
}

}  // namespace
}  // namespace rangecal
