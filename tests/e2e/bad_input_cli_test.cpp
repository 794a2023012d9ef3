// Hostile input through the command line (docs/reliability.md): for each class of bad input, the
// exit code (2 usage/config, 3 input data, 4 calibration; never 1), a message naming file, line and
// field, and the state of the output folder afterwards (nothing stale, nothing half-written).
// A small two-camera mission is simulated once and copied for each case.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/paths.hpp"
#include "support/simulated_mission.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json small_scenario() {
  return json::parse(test::small_two_camera_scenario_text());
}

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

// The simulated mission, once per test process.
const fs::path& pristine_mission() {
  static const fs::path dir = [] {
    const fs::path d = test::scratch_dir("bad_input_pristine");
    test::write_text(d / "scenario.json", small_scenario().dump(2));
    const auto r = test::run_cli("-q simulate " + q(d / "scenario.json") + " --out " + q(d / "mission"));
    if (r.exit_code != 0) throw std::runtime_error("simulate failed: " + r.err);
    return d / "mission";
  }();
  return dir;
}

// A fresh copy of the mission's inputs under scratch "name".
fs::path mission_copy(const std::string& name) {
  const fs::path dst = test::scratch_dir("bad_input_" + name) / "mission";
  test::copy_mission_inputs(pristine_mission(), dst);
  return dst;
}

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string l; std::getline(ss, l);) out.push_back(l);
  return out;
}

std::string join_lines(const std::vector<std::string>& lines, const std::string& eol = "\n") {
  std::string s;
  for (const auto& l : lines) s += l + eol;
  return s;
}

// Replaces the whitespace-separated token `index` of line `line_index` (0-based) with `value`.
void replace_token(std::vector<std::string>* lines, std::size_t line_index, std::size_t index,
                   const std::string& value) {
  std::istringstream in((*lines)[line_index]);
  std::vector<std::string> tok;
  for (std::string t; in >> t;) tok.push_back(t);
  tok.at(index) = value;
  std::string s;
  for (const auto& t : tok) s += (s.empty() ? "" : "  ") + t;
  (*lines)[line_index] = s;
}

std::size_t first_data_line(const std::vector<std::string>& lines) {
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (!lines[i].empty() && lines[i][0] != '%') return i;
  return lines.size();
}

struct Outcome {
  test::CliResult cli;
  double seconds = 0;
};

Outcome run(const std::string& args) {
  const auto t0 = std::chrono::steady_clock::now();
  Outcome o;
  o.cli = test::run_cli("-q " + args);
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return o;
}

// Exit `code`, and the message names "file:line" and the field.
void expect_refused(const Outcome& o, int code, const std::string& file_and_line, const std::string& field) {
  EXPECT_EQ(o.cli.exit_code, code) << o.cli.err;
  EXPECT_NE(o.cli.err.find(file_and_line), std::string::npos)
      << "message lacks '" << file_and_line << "': " << o.cli.err;
  if (!field.empty()) {
    EXPECT_NE(o.cli.err.find("field '" + field), std::string::npos)
        << "message lacks field '" << field << "': " << o.cli.err;
  }
  EXPECT_EQ(o.cli.err.find("internal error"), std::string::npos) << o.cli.err;
  EXPECT_EQ(o.cli.err.find("libpng"), std::string::npos) << o.cli.err;
  EXPECT_EQ(o.cli.err.find("InitGoogleLogging"), std::string::npos) << o.cli.err;
}

bool no_mission_outputs(const fs::path& m) {
  for (const char* f : {"out/gnss/lamp_track.csv", "out/c1/calibration.json", "out/c2/calibration.json",
                        "out/intersection.csv", "out/summary.json", "out/report.html"})
    if (fs::exists(m / f)) {
      ADD_FAILURE() << "stale output left: " << (m / f);
      return false;
    }
  return true;
}

json read_json(const fs::path& p) {
  return json::parse(test::read_text(p));
}

TEST(BadInputCli, TheSmallMissionRunsCleanly) {
  const fs::path m = mission_copy("clean");
  const Outcome o = run("run " + q(m / "mission.json"));
  ASSERT_EQ(o.cli.exit_code, 0) << o.cli.err;
  EXPECT_TRUE(fs::exists(m / "out/c1/calibration.json"));
  EXPECT_TRUE(fs::exists(m / "out/c2/calibration.json"));
  EXPECT_TRUE(fs::exists(m / "out/intersection.csv"));
  const json runlog = read_json(m / "out/run.json");
  EXPECT_EQ(runlog["status"], "ok");
  EXPECT_EQ(runlog["stages"]["report"]["status"], "ok");
  EXPECT_EQ(runlog["outcome"], json({{"status", "complete"}, {"exit_code", 0}, {"reasons", json::array()}}));
  EXPECT_EQ(read_json(m / "out/summary.json")["outcome"], runlog["outcome"]);
  EXPECT_TRUE(o.cli.err.empty()) << "library chatter on a clean run: " << o.cli.err;
}

// ---- 1. numbers out of their physical range, refused at the parser -------------------------

TEST(BadInputCli, PosNumbersOutOfRange) {
  struct Case {
    std::string name;
    std::size_t token;
    std::string value;
    std::string field;
  };
  // Tokens: date time lat lon height Q ns sdn sde sdu sdne sdeu sdun age ratio.
  const std::vector<Case> cases = {{"height_1e12", 4, "1e12", "height(m)"},
                                   {"latitude_95", 2, "95.0", "latitude(deg)"},
                                   {"sdn_negative", 7, "-0.1", "sdn(m)"},
                                   {"ratio_huge", 14, "1e9", "ratio"},
                                   {"year_2263", 0, "2263/01/01", "GPST"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path m = mission_copy("pos_" + c.name);
    auto lines = split_lines(test::read_text(m / "gnss/rover.pos"));
    const std::size_t i = first_data_line(lines) + 20;
    replace_token(&lines, i, c.token, c.value);
    test::write_text(m / "gnss/rover.pos", join_lines(lines));
    const Outcome o = run("run " + q(m / "mission.json"));
    expect_refused(o, 3, "rover.pos:" + std::to_string(i + 1), c.field);
    EXPECT_TRUE(no_mission_outputs(m));
  }
}

TEST(BadInputCli, EcefHeaderOverLatLonColumnsIsRefused) {
  for (const bool keep_ref_pos : {false, true}) {
    SCOPED_TRACE(keep_ref_pos ? "with ref pos" : "without ref pos");
    const fs::path m = mission_copy("pos_ecef_header");
    auto lines = split_lines(test::read_text(m / "gnss/rover.pos"));
    std::size_t ref_pos = 0;
    for (std::size_t k = 0; k < lines.size(); ++k)
      if (lines[k].rfind("% ref pos", 0) == 0) ref_pos = k;
    ASSERT_GT(ref_pos, 0u);
    if (!keep_ref_pos) lines.erase(lines.begin() + static_cast<long>(ref_pos));
    const std::size_t d = first_data_line(lines);
    // The column header says ECEF; the columns are still latitude, longitude, height.
    lines[d - 1] =
        "%  GPST                   x-ecef(m)      y-ecef(m)      z-ecef(m)   Q  ns   sdx(m)   sdy(m)   "
        "sdz(m)  "
        "sdxy(m)  sdyz(m)  sdzx(m) age(s)  ratio";
    test::write_text(m / "gnss/rover.pos", join_lines(lines));
    const Outcome o = run("gnss " + q(m / "mission.json"));
    if (keep_ref_pos) {
      // The header's reference position, read as ECEF, is refused first.
      expect_refused(o, 3, "rover.pos:" + std::to_string(ref_pos + 1), "ref pos");
    } else {
      expect_refused(o, 3, "rover.pos:" + std::to_string(d + 1), "x-ecef(m)");
      EXPECT_NE(o.cli.err.find("Earth's centre"), std::string::npos) << o.cli.err;
    }
    EXPECT_FALSE(fs::exists(m / "out/gnss/lamp_track.csv"));
  }
}

TEST(BadInputCli, PolePickOutsideTheImage) {
  for (const std::string uv : {"5000,40", "100,-10", "199.6,20"}) {
    SCOPED_TRACE(uv);
    const fs::path m = mission_copy("pick_outside");
    auto lines = split_lines(test::read_text(m / "c1/poles_px.csv"));
    ASSERT_GE(lines.size(), 2u);
    lines[1] = lines[1].substr(0, lines[1].find(',')) + "," + uv;
    test::write_text(m / "c1/poles_px.csv", join_lines(lines));
    const Outcome o = run("run " + q(m / "mission.json"));
    expect_refused(o, 3, "poles_px.csv:2", "");
    EXPECT_NE(o.cli.err.find("200x150 image"), std::string::npos) << o.cli.err;
    EXPECT_FALSE(fs::exists(m / "out/intersection.csv"));
    EXPECT_FALSE(fs::exists(m / "out/summary.json"));
  }
}

// A picks file with its header and no pick: refused where it is read (exit 3, bad input data),
// naming the file, the header's line and the field, not left to surface as a partial mission
// without check poles (docs/formats.md "Survey files").
TEST(BadInputCli, PolePicksFileWithoutPicksNamesItself) {
  for (const auto& [text, line] :
       std::vector<std::pair<std::string, int>>{{"id,u,v\n", 1}, {"# cam1 picks\nid,u,v\n\n", 2}}) {
    SCOPED_TRACE(text);
    const fs::path m = mission_copy("picks_empty");
    test::write_text(m / "c1/poles_px.csv", text);
    const Outcome o = run("run " + q(m / "mission.json"));
    expect_refused(o, 3, "c1/poles_px.csv:" + std::to_string(line), "id");
    EXPECT_NE(o.cli.err.find("no pole picks after the header"), std::string::npos) << o.cli.err;
    EXPECT_EQ(o.cli.err.find("partial"), std::string::npos) << o.cli.err;
    EXPECT_FALSE(fs::exists(m / "out/intersection.csv"));
    EXPECT_FALSE(fs::exists(m / "out/summary.json"));
  }
}

TEST(BadInputCli, CorrespondenceCoordinatesOutOfRange) {
  const fs::path m = mission_copy("corr_range");
  ASSERT_EQ(run("run " + q(m / "mission.json")).cli.exit_code, 0);
  for (const std::string column : {"E", "U", "u"}) {
    SCOPED_TRACE(column);
    auto lines = split_lines(test::read_text(m / "out/c1/correspondences.csv"));
    const auto header = split_lines(lines[0]);
    std::vector<std::string> cols;
    std::stringstream hs(lines[0]);
    for (std::string c; std::getline(hs, c, ',');) cols.push_back(c);
    std::vector<std::string> f;
    std::stringstream rs(lines[5]);
    for (std::string c; std::getline(rs, c, ',');) f.push_back(c);
    const auto at = std::find(cols.begin(), cols.end(), column) - cols.begin();
    const std::string saved = lines[5];
    f[at] = "1e12";
    std::string row;
    for (std::size_t k = 0; k < f.size(); ++k) row += (k ? "," : "") + f[k];
    lines[5] = row;
    test::write_text(m / "out/c1/correspondences.csv", join_lines(lines));
    const Outcome o = run("calibrate " + q(m / "mission.json"));
    expect_refused(o, 3, "correspondences.csv:6", column);
    EXPECT_FALSE(fs::exists(m / "out/c1/calibration.json"));
    lines[5] = saved;
    test::write_text(m / "out/c1/correspondences.csv", join_lines(lines));
  }
}

TEST(BadInputCli, TimeStampYearsBeyondTheSupportedSpan) {
  for (const std::string year : {"2263", "1969", "9999"}) {
    SCOPED_TRACE(year);
    const fs::path m = mission_copy("frames_year");
    auto lines = split_lines(test::read_text(m / "c1/timestamps.csv"));
    const std::size_t at = lines[3].rfind(',') + 1;
    lines[3] = lines[3].substr(0, at) + year + lines[3].substr(at + 4);
    test::write_text(m / "c1/timestamps.csv", join_lines(lines));
    const Outcome o = run("run " + q(m / "mission.json"));
    expect_refused(o, 3, "timestamps.csv:4", "utc");
    EXPECT_NE(o.cli.err.find("1970-2200"), std::string::npos) << o.cli.err;
  }
}

// ---- 2. nothing escapes as an internal error --------------------------------------------------

TEST(BadInputCli, JsonNumberBeyondDoubleNamesItsLine) {
  const fs::path m = mission_copy("json_overflow");
  std::string text = test::read_text(m / "mission.json");
  const auto at = text.find("\"max_sd_m\"");
  ASSERT_NE(at, std::string::npos);
  const std::size_t colon = text.find(':', at), comma = text.find_first_of(",}", colon);
  text = text.substr(0, colon + 1) + " 1e999" + text.substr(comma);
  const long line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(at), '\n');
  test::write_text(m / "mission.json", text);
  for (const std::string cmd : {"run", "gnss", "report"}) {
    const Outcome o = run(cmd + " " + q(m / "mission.json"));
    expect_refused(o, 2, "mission.json:" + std::to_string(line), "");
    EXPECT_NE(o.cli.err.find("1e999"), std::string::npos) << o.cli.err;
  }
  EXPECT_FALSE(fs::exists(m / "out"));
}

TEST(BadInputCli, NonUtf8BytesNeverReachTheTerminalOrJson) {
  const fs::path m = mission_copy("non_utf8");
  ASSERT_EQ(run("run " + q(m / "mission.json")).cli.exit_code, 0);
  auto lines = split_lines(test::read_text(m / "survey/poles.csv"));
  lines[1] = "P\xff\x1b[31m" + lines[1].substr(lines[1].find(','));
  test::write_text(m / "survey/poles.csv", join_lines(lines));
  const Outcome o = run("run " + q(m / "mission.json"));
  expect_refused(o, 3, "poles.csv:2", "");
  EXPECT_EQ(o.cli.err.find('\xff'), std::string::npos) << "raw byte echoed";
  EXPECT_EQ(o.cli.err.find('\x1b'), std::string::npos) << "escape sequence echoed";
  EXPECT_NE(o.cli.err.find("0xFF"), std::string::npos) << o.cli.err;
  // run.json records the failure and stays valid JSON.
  const json runlog = read_json(m / "out/run.json");
  EXPECT_EQ(runlog["status"], "failed");
}

TEST(BadInputCli, HugeSimulatedCameraIsRefusedBeforeAnyFileIsWritten) {
  const fs::path dir = test::scratch_dir("bad_input_huge_camera");
  for (const std::string key : {"width_px", "height_px"}) {
    json s = small_scenario();
    s["cameras"][1][key] = 100000;
    test::write_text(dir / "s.json", s.dump(2));
    const Outcome o = run("simulate " + q(dir / "s.json") + " --out " + q(dir / "out"));
    expect_refused(o, 2, "s.json", "cameras[1]." + key);
    EXPECT_FALSE(fs::exists(dir / "out"));
  }
}

// ---- 3. bounded work: refused before it starts ------------------------------------------------

TEST(BadInputCli, DerivedSizesAreBoundedBeforeWorkStarts) {
  const fs::path dir = test::scratch_dir("bad_input_bounded");
  struct Case {
    std::string name;
    std::function<void(json&)> edit;
    std::string field;
  };
  const std::vector<Case> cases = {
      {"gnss_rate", [](json& s) { s["gnss"]["rate_hz"] = 1e9; }, "gnss.rate_hz"},
      {"route_speed", [](json& s) { s["routes"][1]["speed_mps"] = 1e-9; }, "routes[1].speed_mps"},
      {"attitude_rate", [](json& s) { s["attitude"]["rate_hz"] = 1e9; }, "attitude.rate_hz"},
      {"frames", [](json& s) { s["cameras"][0]["fps"] = 1e7, s["cameras"][0]["export_step"] = 1; },
       "cameras[0].export_step"},
      {"hover", [](json& s) { s["routes"][0]["hover_s"] = 1e6; }, "routes[0].hover_s"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    json s = small_scenario();
    c.edit(s);
    test::write_text(dir / (c.name + ".json"), s.dump(2));
    for (const std::string& cmd : {"simulate " + q(dir / (c.name + ".json")) + " --out " + q(dir / "out"),
                                   "plan " + q(dir / (c.name + ".json"))}) {
      const Outcome o = run(cmd);
      expect_refused(o, 2, c.name + ".json", c.field);
      EXPECT_LT(o.seconds, 10.0);
      EXPECT_FALSE(fs::exists(dir / "out"));
    }
  }
}

// ---- 4. no stale output presented as new ------------------------------------------------------

TEST(BadInputCli, AFailedRunLeavesNoOldResults) {
  const fs::path m = mission_copy("failed_rerun");
  ASSERT_EQ(run("run " + q(m / "mission.json")).cli.exit_code, 0);
  ASSERT_TRUE(fs::exists(m / "out/summary.json"));
  // The rerun fails in the gnss stage (a truncated .pos line).
  auto lines = split_lines(test::read_text(m / "gnss/rover.pos"));
  const std::size_t i = first_data_line(lines) + 3;
  lines[i] = lines[i].substr(0, 40);
  test::write_text(m / "gnss/rover.pos", join_lines(lines));
  const Outcome o = run("run " + q(m / "mission.json"));
  expect_refused(o, 3, "rover.pos:" + std::to_string(i + 1), "");
  EXPECT_TRUE(no_mission_outputs(m));
  EXPECT_FALSE(fs::exists(m / "out/c1/aligned.csv"));
  EXPECT_FALSE(fs::exists(m / "out/c1/correspondences.csv"));
  const json runlog = read_json(m / "out/run.json");
  EXPECT_EQ(runlog["status"], "failed");
  EXPECT_EQ(runlog["failed_stage"], "gnss");
  EXPECT_EQ(runlog["stages"]["gnss"]["status"], "failed");
  EXPECT_EQ(runlog["stages"]["gnss"]["error"]["exit_code"], 3);
  EXPECT_EQ(runlog["stages"]["gnss"]["error"]["line"], static_cast<long>(i + 1));
  EXPECT_FALSE(runlog["stages"].contains("calibrate")) << "a section of an older run survived";
  EXPECT_GT(runlog["stages"]["gnss"]["removed_outputs"].get<int>(), 5);
}

TEST(BadInputCli, ACameraThatFailsIsNotUsedDownstream) {
  const fs::path m = mission_copy("camera_fails");
  ASSERT_EQ(run("run " + q(m / "mission.json")).cli.exit_code, 0);
  ASSERT_TRUE(fs::exists(m / "out/c2/calibration.json"));
  // c2's pairs collapse onto one vertical line: its rotation about the line is undetermined.
  auto lines = split_lines(test::read_text(m / "out/c2/correspondences.csv"));
  std::vector<std::string> cols;
  std::stringstream hs(lines[0]);
  for (std::string c; std::getline(hs, c, ',');) cols.push_back(c);
  const auto ce = std::find(cols.begin(), cols.end(), "E") - cols.begin();
  const auto cn = std::find(cols.begin(), cols.end(), "N") - cols.begin();
  for (std::size_t r = 1; r < lines.size(); ++r) {
    std::vector<std::string> f;
    std::stringstream rs(lines[r]);
    for (std::string c; std::getline(rs, c, ',');) f.push_back(c);
    f[ce] = "0.1000";
    f[cn] = "0.2000";
    std::string row;
    for (std::size_t k = 0; k < f.size(); ++k) row += (k ? "," : "") + f[k];
    lines[r] = row;
  }
  test::write_text(m / "out/c2/correspondences.csv", join_lines(lines));
  // A stale compared-method file and a dead process's temp file are cleaned up too.
  test::write_text(m / "out/c2/calibration_tsai.json", "{}");
  test::write_text(m / "out/c1/calibration.json.tmp.4194302", "half");
  // Each command leaves a partial mission (c2 not calibrated, so no pole can be triangulated):
  // exit 4, naming run.json's outcome and why, the outputs of c1 kept (docs/reliability.md "Run
  // outcome").
  for (const std::string stage : {"calibrate", "intersect", "report"}) {
    const Outcome o = run(stage + " " + q(m / "mission.json"));
    EXPECT_EQ(o.cli.exit_code, 4) << stage << ": " << o.cli.err;
    EXPECT_NE(o.cli.err.find((m / "out/run.json").string() + ": field 'outcome': the mission is partial"),
              std::string::npos)
        << stage << ": " << o.cli.err;
    EXPECT_NE(o.cli.err.find("calibrate: camera c2 not calibrated (from " +
                             (m / "out/c2/correspondences.csv").string() + ")"),
              std::string::npos)
        << stage << ": " << o.cli.err;
  }
  EXPECT_FALSE(fs::exists(m / "out/c2/calibration.json"));
  EXPECT_FALSE(fs::exists(m / "out/c2/calibration_tsai.json"));
  EXPECT_FALSE(fs::exists(m / "out/c1/calibration.json.tmp.4194302"));
  EXPECT_TRUE(fs::exists(m / "out/c1/calibration.json"));
  const json runlog = read_json(m / "out/run.json");
  EXPECT_NE(runlog["stages"]["calibrate"]["counts"]["cameras"]["c2"]["failed"].get<std::string>().find(
                "lie in one"),
            std::string::npos);
  EXPECT_EQ(runlog["stages"]["intersect"]["counts"]["cameras_used"], json::array({"c1"}));
  const json summary = read_json(m / "out/summary.json");
  EXPECT_EQ(summary["cameras"]["c1"]["calibrated"], true);
  EXPECT_EQ(summary["cameras"]["c2"]["calibrated"], false);
  EXPECT_NE(summary["cameras"]["c2"]["failure"].get<std::string>().find("lie in one"), std::string::npos);
  EXPECT_EQ(runlog["outcome"]["status"], "partial");
  EXPECT_EQ(runlog["outcome"]["exit_code"], 4);
  ASSERT_EQ(runlog["outcome"]["reasons"].size(), 2u) << runlog["outcome"];
  EXPECT_NE(runlog["outcome"]["reasons"][1].get<std::string>().find(
                "intersect: no check pole was triangulated, so the intersection check has no dR: only 1 "
                "calibrated camera has pole picks (c1)"),
            std::string::npos)
      << runlog["outcome"];
  EXPECT_EQ(summary["outcome"], runlog["outcome"]);
  EXPECT_EQ(runlog["status"], "ok");  // every stage ran to its end; the outcome says what is missing
}

// ---- the run's outcome (docs/reliability.md "Run outcome") -------------------------------------

// No figure that was not computed is printed or written: no "nan" or "inf" word anywhere.
void expect_no_undefined_numbers(const std::string& what, const std::string& text) {
  static const std::regex word("\\b(nan|NaN|NAN|-?inf|-?Inf|Infinity)\\b");
  std::smatch hit;
  EXPECT_FALSE(std::regex_search(text, hit, word)) << what << " holds '" << hit.str() << "'";
}

// A camera left with one lamp pair: c1 (no control pole picked) cannot be calibrated, c2 is
// calibrated from its six control poles and its pairs, and no pole can be triangulated with one
// camera. Each stage goes to its end, keeps what it made, and exits 4 saying both, never 0 with
// "mean dR nan mm" (the state a .pos of one epoch used to leave, before the gnss stage refused it).
TEST(BadInputCli, OnePairIsAPartialMissionExitFourWithItsOutputsMarked) {
  json scenario = small_scenario();
  scenario["poles"] = json::array();
  const std::vector<std::array<double, 3>> control = {{0.5, 0.4, 3.2},  {-1.5, 1.0, 1.0}, {1.4, -0.8, 4.0},
                                                      {-0.7, 2.0, 2.5}, {1.8, 1.5, 1.5},  {-1.9, -1.2, 3.8}};
  for (std::size_t i = 0; i < control.size(); ++i)
    scenario["poles"].push_back(
        {{"id", "P" + std::to_string(i + 1)}, {"role", "control"}, {"enu_m", control[i]}});
  scenario["poles"].push_back({{"id", "Q1"}, {"role", "check"}, {"enu_m", {-0.6, -0.5, 2.1}}});
  scenario["poles"].push_back({{"id", "Q2"}, {"role", "check"}, {"enu_m", {0.3, 1.2, 3.0}}});
  const fs::path d = test::scratch_dir("bad_input_one_pair");
  test::write_text(d / "scenario.json", scenario.dump(2));
  ASSERT_EQ(run("simulate " + q(d / "scenario.json") + " --out " + q(d / "mission")).cli.exit_code, 0);
  const fs::path m = d / "mission";
  json cfg = read_json(m / "mission.json");
  cfg["calibrate"]["use_control_poles"] = true;
  test::write_text(m / "mission.json", cfg.dump(2));
  std::string c1_picks = "id,u,v\n";
  for (const std::string& l : split_lines(test::read_text(m / "c1/poles_px.csv")))
    if (l.rfind("Q", 0) == 0) c1_picks += l + "\n";
  test::write_text(m / "c1/poles_px.csv", c1_picks);
  ASSERT_EQ(run("run " + q(m / "mission.json")).cli.exit_code, 0);
  // c1 keeps the middle one of its lamp pairs.
  auto pairs = split_lines(test::read_text(m / "out/c1/correspondences.csv"));
  ASSERT_GT(pairs.size(), 3u);
  test::write_text(m / "out/c1/correspondences.csv", pairs[0] + "\n" + pairs[pairs.size() / 2] + "\n");

  for (const std::string stage : {"calibrate", "intersect", "report"}) {
    const test::CliResult o = test::run_cli(stage + " " + q(m / "mission.json"));  // not quiet
    EXPECT_EQ(o.exit_code, 4) << stage << ": " << o.err;
    EXPECT_NE(o.err.find((m / "out/run.json").string() + ": field 'outcome': the mission is partial"),
              std::string::npos)
        << o.err;
    if (stage == "intersect") {
      EXPECT_NE(o.out.find("no check pole triangulated: no mean dR"), std::string::npos) << o.out;
    }
    expect_no_undefined_numbers("the console", o.out + o.err);
  }
  EXPECT_TRUE(fs::exists(m / "out/c2/calibration.json"));
  EXPECT_FALSE(fs::exists(m / "out/c1/calibration.json"));
  EXPECT_TRUE(fs::exists(m / "out/intersection.csv"));
  EXPECT_TRUE(fs::exists(m / "out/report.html"));
  const json runlog = read_json(m / "out/run.json");
  EXPECT_EQ(runlog["status"], "ok");
  EXPECT_EQ(runlog["outcome"]["status"], "partial");
  EXPECT_EQ(runlog["outcome"]["exit_code"], 4);
  ASSERT_EQ(runlog["outcome"]["reasons"].size(), 2u) << runlog["outcome"];
  EXPECT_EQ(runlog["outcome"]["reasons"][0].get<std::string>().rfind(
                "calibrate: camera c1 not calibrated (from " + (m / "out/c1/correspondences.csv").string() +
                    "): field 'dlt': too few points: 1 given",
                0),
            0u)
      << runlog["outcome"];
  EXPECT_EQ(runlog["outcome"]["reasons"][1],
            "intersect: no check pole was triangulated, so the intersection check has no dR: only 1 "
            "calibrated camera has pole picks (c2); a pole needs two");
  EXPECT_EQ(runlog["stages"]["calibrate"]["shortfalls"].size(), 1u);
  EXPECT_EQ(runlog["stages"]["intersect"]["counts"]["poles_triangulated"], 0);
  const json summary = read_json(m / "out/summary.json");
  EXPECT_EQ(summary["outcome"], runlog["outcome"]);
  const std::string html = test::read_text(m / "out/report.html");
  EXPECT_NE(html.find("This mission is partial (exit 4)"), std::string::npos);
  for (const char* f : {"out/run.json", "out/summary.json", "out/report.html"})
    expect_no_undefined_numbers(f, test::read_text(m / f));
}

// A .pos holding one epoch is refused where that is first known, the gnss stage: exit 3 naming the
// .pos, the epoch's line and what is missing (docs/gnss.md "Filtering and gaps"), not a camera's
// calibration several stages later.
TEST(BadInputCli, OneEpochIsRefusedAtTheGnssStageNamingThePos) {
  const fs::path m = mission_copy("one_epoch");
  auto lines = split_lines(test::read_text(m / "gnss/rover.pos"));
  const std::size_t first = first_data_line(lines);
  const std::string epoch = lines[first + (lines.size() - first) / 2];
  lines.resize(first);
  lines.push_back(epoch);
  test::write_text(m / "gnss/rover.pos", join_lines(lines));
  const Outcome o = run("run " + q(m / "mission.json"));
  expect_refused(o, 3, "rover.pos:" + std::to_string(first + 1), "epochs");
  EXPECT_NE(o.cli.err.find("only 1 epoch is left for the lamp track (1 read"), std::string::npos)
      << o.cli.err;
  EXPECT_NE(o.cli.err.find("needs at least 2"), std::string::npos) << o.cli.err;
  EXPECT_TRUE(no_mission_outputs(m));
  const json runlog = read_json(m / "out/run.json");
  EXPECT_EQ(runlog["status"], "failed");
  EXPECT_EQ(runlog["failed_stage"], "gnss");
}

// Poorly determined parameters are warnings (the small mission has some: exit 0 above) unless
// run.fail_on_poorly_determined asks for a partial run; a value that is not a boolean is a config
// error naming the key.
TEST(BadInputCli, PoorlyDeterminedParametersFailTheRunOnlyWhenAsked) {
  const fs::path m = mission_copy("poorly_determined");
  json cfg = read_json(m / "mission.json");
  cfg["run"] = {{"fail_on_poorly_determined", true}};
  test::write_text(m / "mission.json", cfg.dump(2));
  const Outcome o = run("run " + q(m / "mission.json"));
  EXPECT_EQ(o.cli.exit_code, 4) << o.cli.err;
  EXPECT_NE(o.cli.err.find("field 'outcome'"), std::string::npos) << o.cli.err;
  const json runlog = read_json(m / "out/run.json");
  ASSERT_FALSE(runlog["outcome"]["reasons"].empty());
  for (const json& r : runlog["outcome"]["reasons"]) {
    EXPECT_EQ(r.get<std::string>().rfind("calibrate: camera c", 0), 0u) << r;
    EXPECT_NE(r.get<std::string>().find(" is poorly determined: "), std::string::npos) << r;
    EXPECT_NE(r.get<std::string>().find("(run.fail_on_poorly_determined is true)"), std::string::npos) << r;
  }
  // Every output is there: the run is complete in its files, partial in its outcome.
  for (const char* f : {"out/c1/calibration.json", "out/c2/calibration.json", "out/intersection.csv",
                        "out/summary.json", "out/report.html"})
    EXPECT_TRUE(fs::exists(m / f)) << f;
  EXPECT_EQ(read_json(m / "out/summary.json")["outcome"]["status"], "partial");

  cfg["run"] = {{"fail_on_poorly_determined", 1}};
  test::write_text(m / "mission.json", cfg.dump(2));
  expect_refused(run("run " + q(m / "mission.json")), 2, "mission.json", "run.fail_on_poorly_determined");
}

// ---- 5. valid input in other spellings: CRLF, byte-order mark ---------------------------------

TEST(BadInputCli, CrlfAndByteOrderMarkGiveTheSameResults) {
  const fs::path a = mission_copy("crlf_ref");
  ASSERT_EQ(run("run " + q(a / "mission.json")).cli.exit_code, 0);
  const fs::path b = mission_copy("crlf_bom");
  for (const char* f : {"gnss/rover.pos", "gnss/attitude.csv", "c1/timestamps.csv", "c2/timestamps.csv",
                        "survey/poles.csv", "c1/poles_px.csv", "mission.json"}) {
    std::string text;
    for (char c : test::read_text(b / f)) {
      if (c == '\r') continue;
      if (c == '\n') text += '\r';
      text += c;
    }
    test::write_text(b / f, "\xEF\xBB\xBF" + text);
  }
  // A .pos converted twice ("\r\r\n").
  std::string pos = test::read_text(b / "gnss/rover.pos");
  std::string twice;
  for (char c : pos) {
    if (c == '\n') twice += '\r';
    twice += c;
  }
  test::write_text(b / "gnss/rover.pos", twice);
  const Outcome o = run("run " + q(b / "mission.json"));
  ASSERT_EQ(o.cli.exit_code, 0) << o.cli.err;
  for (const char* f : {"out/gnss/lamp_track.csv", "out/c1/correspondences.csv", "out/c1/calibration.json",
                        "out/intersection.csv"})
    EXPECT_EQ(test::read_text(a / f), test::read_text(b / f)) << f;
}

// ---- 6. a key given twice --------------------------------------------------------------------

TEST(BadInputCli, DuplicateJsonKeyNamesBothLines) {
  const fs::path m = mission_copy("dup_key");
  std::string text = test::read_text(m / "mission.json");
  const auto at = text.find("\"max_sd_m\"");
  ASSERT_NE(at, std::string::npos);
  const long first = 1 + std::count(text.begin(), text.begin() + static_cast<long>(at), '\n');
  text.insert(at, "\"max_sd_m\": 0.5,\n      ");
  test::write_text(m / "mission.json", text);
  const Outcome o = run("run " + q(m / "mission.json"));
  expect_refused(o, 2, "mission.json:" + std::to_string(first + 1), "max_sd_m");
  EXPECT_NE(o.cli.err.find("lines " + std::to_string(first) + " and " + std::to_string(first + 1)),
            std::string::npos)
      << o.cli.err;
}

// A camera named as one of the mission's own outputs or records ("gnss" is the track's folder,
// "network" and "method_choice" the calibrate stage's mission-level records) is refused at load,
// before any stage writes.
TEST(BadInputCli, ReservedCameraIdIsRefusedNamingFileAndField) {
  const fs::path m = mission_copy("reserved_id");
  std::string text = test::read_text(m / "mission.json");
  const auto at = text.find("\"c1\"");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 4, "\"network\"");
  test::write_text(m / "mission.json", text);
  const Outcome o = run("run " + q(m / "mission.json"));
  // A value the schema refuses is named by its JSON path (as every config check), not a line.
  expect_refused(o, 2, (m / "mission.json").string() + ": field 'cameras[0].id'", "cameras[0].id");
  EXPECT_NE(o.cli.err.find("'network' is reserved"), std::string::npos) << o.cli.err;
  EXPECT_TRUE(no_mission_outputs(m));
}

// ---- 7. messages -------------------------------------------------------------------------------

TEST(BadInputCli, CalibrationFailureNamesTheCorrespondencesFile) {
  const fs::path m = mission_copy("calib_fails");
  ASSERT_EQ(run("run " + q(m / "mission.json")).cli.exit_code, 0);
  for (const char* cam : {"c1", "c2"}) {
    auto lines = split_lines(test::read_text(m / "out" / cam / "correspondences.csv"));
    lines.resize(4);  // three pairs: fewer equations than unknowns
    test::write_text(m / "out" / cam / "correspondences.csv", join_lines(lines));
  }
  const Outcome o = run("calibrate " + q(m / "mission.json"));
  EXPECT_EQ(o.cli.exit_code, 4) << o.cli.err;
  EXPECT_NE(o.cli.err.find("correspondences.csv"), std::string::npos) << o.cli.err;
  EXPECT_FALSE(fs::exists(m / "out/c1/calibration.json"));
  EXPECT_EQ(read_json(m / "out/run.json")["stages"]["calibrate"]["status"], "failed");
}

TEST(BadInputCli, BrokenPngFrameIsReportedWithoutLibraryChatter) {
  const fs::path m = mission_copy("broken_png");
  const auto lines = split_lines(test::read_text(m / "c1/timestamps.csv"));
  // frame,file,utc with the file relative to the CSV's folder; a frame in the middle of the flight.
  const std::size_t row = lines.size() / 2;
  const std::string& l = lines[row];
  const std::string file = l.substr(l.find(',') + 1, l.rfind(',') - l.find(',') - 1);
  const std::string bytes = test::read_text(m / "c1" / file);
  test::write_text(m / "c1" / file, bytes.substr(0, bytes.size() / 2));
  const Outcome o = run("run " + q(m / "mission.json"));
  expect_refused(o, 3, "timestamps.csv:" + std::to_string(row + 1), "file");
  EXPECT_FALSE(fs::exists(m / "out/c1/correspondences.csv"));
}

}  // namespace
}  // namespace rangecal
