// What the command line prints for a person at the console (docs/cli.md): a mistyped command
// names the nearest, -q/-v work after the command, a stage that drops most of the real PPK file
// says why and which key to change, and `run` prints readable per-stage lines, not JSON.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/paths.hpp"
#include "support/simulated_mission.hpp"

namespace rangecal {
namespace {
namespace fs = std::filesystem;

// The real Galway kinematic solution (tests/data/external/gnss), gnss stage only.
fs::path galway_config(const std::string& name, const std::string& accept) {
  const fs::path dir = test::scratch_dir(name);
  test::write_text(dir / "mission.json",
                   R"({"site": {"origin": {"lat": 53.282695790, "lon": -8.982135671, "h": 87.4012}},
  "gnss": {"pos_files": [")" +
                       test::external("gnss/pos/rover20181009_kin_llh_gpst.pos").string() +
                       R"("], "accept_quality": )" + accept + R"(, "max_sd_m": 0.05, "max_gap_s": 1.5},
  "lever_arm": {"vertical_m": 0.25}, "cameras": [], "output_dir": "out"})");
  return dir / "mission.json";
}

// Epochs of the real file by Q, counted here independently of the reader: column 6 of every
// line that is not a '%' comment.
std::pair<int, int> count_fix_and_float() {
  std::istringstream in(test::read_text(test::external("gnss/pos/rover20181009_kin_llh_gpst.pos")));
  std::string line;
  int fix = 0, flt = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '%') continue;
    std::istringstream f(line);
    std::string date, time, lat, lon, h;
    int q = 0;
    f >> date >> time >> lat >> lon >> h >> q;
    fix += q == 1;
    flt += q == 2;
  }
  return {fix, flt};
}

std::string thousands(int n) {
  std::string s = std::to_string(n);
  for (int i = static_cast<int>(s.size()) - 3; i > 0; i -= 3) s.insert(static_cast<std::size_t>(i), ",");
  return s;
}

TEST(ConsoleCli, MistypedCommandNamesTheNearest) {
  const test::CliResult r = test::run_cli("calibarte mission.json");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown command 'calibarte' (did you mean 'calibrate'?)"), std::string::npos)
      << r.err;
  const test::CliResult far = test::run_cli("frobnicate");
  EXPECT_EQ(far.exit_code, 2);
  EXPECT_NE(far.err.find("unknown command 'frobnicate'; commands: run, gnss"), std::string::npos) << far.err;
  EXPECT_EQ(far.err.find("did you mean"), std::string::npos) << far.err;
}

TEST(ConsoleCli, QuietAndVerboseAfterTheCommand) {
  const fs::path cfg = galway_config("console_quiet", "[1]");
  const test::CliResult quiet = test::run_cli("gnss -q '" + cfg.string() + "'");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_EQ(quiet.out, "");
  const test::CliResult quiet_after = test::run_cli("gnss '" + cfg.string() + "' --quiet");
  ASSERT_EQ(quiet_after.exit_code, 0) << quiet_after.err;
  EXPECT_EQ(quiet_after.out, "");
  const test::CliResult verbose = test::run_cli("gnss -v '" + cfg.string() + "'");
  ASSERT_EQ(verbose.exit_code, 0) << verbose.err;
  EXPECT_NE(verbose.out.find(" .. "), std::string::npos) << verbose.out;  // the gap list
}

TEST(ConsoleCli, MostlyFloatEpochsAreExplainedWithTheKeyToChange) {
  const auto [fix, flt] = count_fix_and_float();
  ASSERT_GT(flt, fix);  // the real file: most epochs are float
  const test::CliResult r = test::run_cli("gnss '" + galway_config("console_float", "[1]").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string expected = thousands(flt) + " of " + thousands(fix + flt) +
                               " epochs are float (Q=2) and were dropped: accept them with "
                               "gnss.accept_quality [1, 2]";
  EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  // Accepting float epochs: no warning.
  const test::CliResult both =
      test::run_cli("gnss '" + galway_config("console_float_ok", "[1, 2]").string() + "'");
  ASSERT_EQ(both.exit_code, 0) << both.err;
  EXPECT_EQ(both.err.find("epochs are float"), std::string::npos) << both.err;
}

TEST(ConsoleCli, RunPrintsOneReadableBlockPerStage) {
  const fs::path dir = test::scratch_dir("console_run");
  test::write_text(dir / "scenario.json", test::small_two_camera_scenario_text());
  const test::CliResult sim = test::run_cli("-q simulate '" + (dir / "scenario.json").string() + "' --out '" +
                                            (dir / "m").string() + "'");
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const test::CliResult run = test::run_cli("run '" + (dir / "m/mission.json").string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // Each stage a titled block of plain lines with the counts read from run.json, never a JSON dump.
  const auto runlog = nlohmann::json::parse(test::read_text(dir / "m/out/run.json"));
  const auto& st = runlog["stages"];
  for (const char* stage : {"gnss (", "align (", "detect (", "calibrate (", "intersect (", "report ("})
    EXPECT_NE(("\n" + run.out).find(std::string("\n") + stage), std::string::npos) << stage << "\n"
                                                                                   << run.out;
  EXPECT_NE(
      run.out.find(std::to_string(st["gnss"]["counts"]["epochs_read"].get<int>()) + " epochs read (Q1 "),
      std::string::npos)
      << run.out;
  for (const char* cam : {"c1", "c2"}) {
    const auto& a = st["align"]["counts"][cam];
    EXPECT_NE(run.out.find(std::string(cam) + ": " + std::to_string(a["frames_aligned"].get<int>()) + " of " +
                           std::to_string(a["frames"].get<int>()) + " frames aligned"),
              std::string::npos)
        << run.out;
    const auto& d = st["detect"]["counts"][cam];
    EXPECT_NE(run.out.find(std::string(cam) + ": lamp in " + std::to_string(d["correspondences"].get<int>()) +
                           " of " + std::to_string(d["frames_examined"].get<int>()) + " frames"),
              std::string::npos)
        << run.out;
    const auto& c = st["calibrate"]["counts"]["cameras"][cam];
    EXPECT_NE(run.out.find(std::string(cam) + ": " + c["method"].get<std::string>() + ", " +
                           std::to_string(c["n_used"].get<int>()) + " points used"),
              std::string::npos)
        << run.out;
  }
  // The report's flight-volume prediction (run.json stages.report.counts.prediction), rounded for
  // reading; this mission's config names the bundle, so there is no network datum floor.
  const auto& pred = st["report"]["counts"]["prediction"];
  ASSERT_TRUE(pred["median_sigma_m"].is_number()) << pred.dump();
  EXPECT_TRUE(pred["over_datum_floor"].is_null()) << pred.dump();
  char line[160];
  std::snprintf(line, sizeof line, "flight volume: intersection sigma %.1f mm median (max %.1f mm)\n",
                pred["median_sigma_m"].get<double>() * 1e3, pred["max_sigma_m"].get<double>() * 1e3);
  EXPECT_NE(run.out.find(line), std::string::npos) << line << run.out;

  // Calibrated by the network instead, the report stage's line sets the σ beside the datum floor.
  auto cfg = nlohmann::json::parse(test::read_text(dir / "m/mission.json"));
  cfg["calibrate"]["method"] = "network";
  test::write_text(dir / "m/mission.json", cfg.dump());
  const std::string mission = "'" + (dir / "m/mission.json").string() + "'";
  ASSERT_EQ(test::run_cli("-q calibrate " + mission).exit_code, 0);
  const test::CliResult report = test::run_cli("report " + mission);
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const auto net = nlohmann::json::parse(
      test::read_text(dir / "m/out/run.json"))["stages"]["report"]["counts"]["prediction"];
  ASSERT_TRUE(net["over_datum_floor"].is_number()) << net.dump();
  const double ratio = net["over_datum_floor"].get<double>();
  EXPECT_GE(ratio, 1.0);
  std::snprintf(
      line, sizeof line, "; datum floor %.1f mm (%.2fx): %s\n",
      net["datum_floor_median_sigma_m"].get<double>() * 1e3, ratio,
      ratio <= 1.25 ? "the PPK fixes and control limit it, not the images" : "the images still limit it");
  EXPECT_NE(report.out.find(line), std::string::npos) << line << report.out;
  EXPECT_EQ(run.out.find("{\""), std::string::npos) << run.out;
}

}  // namespace
}  // namespace rangecal
