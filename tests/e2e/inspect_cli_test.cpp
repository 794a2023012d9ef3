// `rangecal inspect` through the binary: the table and --json on the real files of
// tests/data/external, several files side by side with their overlap, and exit 3 naming a file of no
// known kind while the readable files are still shown.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "support/paths.hpp"

namespace rangecal {
namespace {

std::string q(const std::filesystem::path& p) {
  return "'" + p.string() + "'";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(InspectCli, TableShowsTheHeaderFactsOfARealCineAndMraw) {
  const auto r = test::run_cli("inspect " + q(test::external("phantom-cine/chart1.cine")) + " " +
                               q(test::external("photron-mraw/ball_12bit.cihx")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  for (const char* part :
       {"Phantom .cine", "2,775,328 bytes", "2048 x 1080 px", "16 stored", "frames IRIG-synchronised",
        "trigger time", "Photron .mraw", "384 x 384 px, 12 bits", "3,317,760 bytes", "30000 Hz",
        "2023-01-18T11:56:13", "time spans (UTC)", "timeline", "overlap"})
    EXPECT_TRUE(contains(r.out, part)) << "missing '" << part << "' in\n" << r.out;
}

TEST(InspectCli, JsonOfTwoPosFilesInDifferentTimeSystemsShowsTheSameSpanAndFullOverlap) {
  const auto r =
      test::run_cli("inspect --json " + q(test::external("gnss/pos/rover20181009_kin_llh_gpst.pos")) + " " +
                    q(test::external("gnss/pos/rover20181009_kin_llh_jst_opts_vel.pos")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["files"].size(), 2u);
  for (const auto& f : j["files"]) {
    EXPECT_EQ(f["kind"], "RTKLIB .pos");
    EXPECT_EQ(f["counts"]["epochs"], 1878);
    EXPECT_EQ(f["counts"]["epochs Q=1 (fix)"], 444);
    EXPECT_EQ(f["counts"]["epochs Q=2 (float)"], 1434);
    EXPECT_EQ(f["utc"]["first"], "2018-10-09T12:21:53.000000000Z");
    EXPECT_EQ(f["rate_hz"], 1.0);
  }
  EXPECT_EQ(j["files"][0]["time_system"].get<std::string>().substr(0, 4), "GPST");
  EXPECT_EQ(j["files"][1]["time_system"].get<std::string>().substr(0, 3), "JST");
  ASSERT_EQ(j["comparisons"].size(), 1u);
  EXPECT_EQ(j["comparisons"][0]["relation"], "overlap");
  EXPECT_EQ(j["comparisons"][0]["overlap_s"], j["files"][0]["utc"]["duration_s"]);
  EXPECT_TRUE(j["errors"].empty());
}

TEST(InspectCli, UlogAndPosDaysApartAreReportedAsAClockNotSet) {
  const auto r = test::run_cli("inspect " + q(test::external("gnss/pos/rover20181009_kin_llh_utc.pos")) +
                               " " + q(test::external("px4-ulog/sample_log_small.ulg")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "PX4 ULog")) << r.out;
  EXPECT_TRUE(contains(r.out, "messages vehicle_attitude")) << r.out;
  EXPECT_TRUE(contains(r.out, "1 vs 2: no overlap")) << r.out;
  EXPECT_TRUE(contains(r.out, "clock not set (date)")) << r.out;
}

TEST(InspectCli, AFileOfNoKnownKindExitsThreeNamingItAndTheOthersAreStillShown) {
  const std::string source = test::external("phantom-cine/SOURCE.md").string();
  const auto r = test::run_cli("inspect " + q(test::external("photron-mraw/beam.mraw")) + " " + q(source));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(contains(r.out, "1024 x 80 px, 12 bits (16 stored)")) << r.out;
  EXPECT_TRUE(contains(r.err, source + ": not a kind of file rangecal reads")) << r.err;
  const auto missing = test::run_cli("inspect /nonexistent/x.cine");
  EXPECT_EQ(missing.exit_code, 3);
  EXPECT_TRUE(contains(missing.err, "/nonexistent/x.cine: no such file")) << missing.err;
  EXPECT_EQ(test::run_cli("inspect").exit_code, 2);  // no file: usage
}

}  // namespace
}  // namespace rangecal

namespace rangecal {
namespace {

// The real pymavlink log is cut 24 bytes into its last message (tests/data/external/
// ardupilot-dataflash/SOURCE.md): inspect says so once, in the table and in --json alike.
TEST(InspectCli, TruncatedDataflashLogIsNotedOnce) {
  const std::string path = q(test::external("ardupilot-dataflash/pymavlink_test.BIN"));
  const auto count = [](const std::string& s, const std::string& part) {
    int n = 0;
    for (std::size_t at = s.find(part); at != std::string::npos; at = s.find(part, at + 1)) ++n;
    return n;
  };
  const auto r = test::run_cli("inspect " + path);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(count(r.out + r.err, "incomplete"), 1) << r.out << r.err;
  EXPECT_EQ(count(r.out, "24 bytes of an incomplete last message"), 1) << r.out;
  const auto j = test::run_cli("inspect --json " + path);
  ASSERT_EQ(j.exit_code, 0) << j.err;
  EXPECT_EQ(count(j.out + j.err, "incomplete"), 1) << j.out << j.err;
}

}  // namespace
}  // namespace rangecal
