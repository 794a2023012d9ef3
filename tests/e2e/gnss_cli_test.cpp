// Bad input to the gnss stage through the real CLI (docs/accuracy_analysis.md, Quality bars): each bad input
// to `rangecal gnss CONFIG` gives exit code 2 (usage/config) or 3 (input) and a message naming the file, the
// line and the field, and writes no lamp track. The .pos content is the head of a real RTKLIB file
// (tests/data/external/gnss/pos/rover20181009_kin_llh_gpst.pos), edited per case.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "support/paths.hpp"

namespace rangecal {
namespace {
namespace fs = std::filesystem;

// Header (11 lines) and the first 4 epochs of the real file; epochs are lines 12–15.
std::string real_head() {
  const std::string text = test::read_text(test::external("gnss/pos/rover20181009_kin_llh_gpst.pos"));
  std::size_t pos = 0;
  for (int i = 0; i < 15; ++i) pos = text.find('\n', pos) + 1;
  return text.substr(0, pos);
}

std::string replace_once(std::string s, const std::string& from, const std::string& to) {
  const std::size_t i = s.find(from);
  EXPECT_NE(i, std::string::npos) << from;
  if (i != std::string::npos) s.replace(i, from.size(), to);
  return s;
}

std::string config(const std::string& pos_name, const std::string& extra = "") {
  return R"({"site": {"origin": {"lat": 53.282695790, "lon": -8.982135671, "h": 87.4012}},
  "gnss": {"pos_files": [")" +
         pos_name + R"("], "accept_quality": [1, 2], "max_sd_m": 5.0)" + extra + R"(},
  "lever_arm": {"vertical_m": 0.25}, "cameras": [], "output_dir": "out"})";
}

struct Case {
  const char* name;
  std::string pos;    // .pos content ("" = do not write the file)
  std::string cfg;    // config text
  int exit_code;      // expected
  std::string where;  // expected in stderr: "file:line"-style locator
  std::string field;  // expected in stderr
};

void expect_case(const Case& c) {
  const fs::path dir = test::scratch_dir(std::string("gnss_cli_") + c.name);
  if (!c.pos.empty()) test::write_text(dir / "rover.pos", c.pos);
  test::write_text(dir / "mission.json", c.cfg);
  const test::CliResult r = test::run_cli("gnss '" + (dir / "mission.json").string() + "'");
  EXPECT_EQ(r.exit_code, c.exit_code) << c.name << ": " << r.err;
  EXPECT_NE(r.err.find(c.where), std::string::npos) << c.name << ": " << r.err;
  EXPECT_NE(r.err.find(c.field), std::string::npos) << c.name << ": " << r.err;
  EXPECT_FALSE(fs::exists(dir / "out/gnss/lamp_track.csv")) << c.name << ": no half-written output";
}

TEST(GnssCli, GoodHeadOfTheRealFileRuns) {
  const fs::path dir = test::scratch_dir("gnss_cli_good");
  test::write_text(dir / "rover.pos", real_head());
  test::write_text(dir / "mission.json", config("rover.pos"));
  const test::CliResult r = test::run_cli("gnss '" + (dir / "mission.json").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string track = test::read_text(dir / "out/gnss/lamp_track.csv");
  EXPECT_EQ(std::count(track.begin(), track.end(), '\n'), 5);  // header + 4 epochs
}

TEST(GnssCli, TruncatedLine) {
  std::string pos = real_head();
  pos = replace_once(pos, "   2  14   0.5010   0.4165   0.8481   0.3110  -0.1540  -0.2960   4.99    1.1",
                     "   2");
  expect_case({"truncated", pos, config("rover.pos"), 3, "rover.pos:13", "ns"});
}

TEST(GnssCli, NonNumericField) {
  expect_case({"nonnumeric", replace_once(real_head(), "89.2251", "89.2x51"), config("rover.pos"), 3,
               "rover.pos:13", "height(m)"});
}

TEST(GnssCli, QualityOutsideOneToSix) {
  expect_case({"q7", replace_once(real_head(), "89.2251   2", "89.2251   7"), config("rover.pos"), 3,
               "rover.pos:13", "Q"});
}

TEST(GnssCli, TimeGoingBackwards) {
  expect_case({"backwards", replace_once(real_head(), "2018/10/09 12:22:13.000", "2018/10/09 12:22:10.000"),
               config("rover.pos"), 3, "rover.pos:14", "GPST"});
}

TEST(GnssCli, FileWithNoEpochs) {
  std::string head = real_head();
  head = head.substr(0, head.find("2018/10/09 12:22:11"));
  expect_case({"noepochs", head, config("rover.pos"), 3, "rover.pos", "epochs"});
}

TEST(GnssCli, MissingPosFile) {
  expect_case({"missing", "", config("nowhere.pos"), 2, "nowhere.pos", "gnss.pos_files[0]"});
}

TEST(GnssCli, ConfigTypo) {
  expect_case({"typo", real_head(), config("rover.pos", R"(, "max_gap_sec": 1.0)"), 2, "mission.json",
               "gnss.max_gap_sec"});
}

}  // namespace
}  // namespace rangecal
