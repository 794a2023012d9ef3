// A mission whose frame stamps are a day off (the camera's date set wrong) fails the align stage
// with exit 3, a message holding the lamp track's and each camera's UTC span and the likely cause,
// and run.json recording the failed align stage (docs/alignment.md "When nothing aligns").
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"
#include "support/paths.hpp"
#include "support/simulated_mission.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string l; std::getline(ss, l);)
    if (!l.empty()) out.push_back(l);
  return out;
}

// The utc column of a CSV data line: the last field of a timestamps CSV (frame,file,utc)…
UtcTime utc_field(const std::string& line) {
  const auto t = parse_iso8601_utc(line.substr(line.rfind(',') + 1));
  EXPECT_TRUE(t.has_value()) << line;
  return t.value_or(UtcTime{});
}
// … the first of lamp_track.csv (utc,E,N,U,…).
UtcTime first_field_utc(const std::string& line) {
  const auto t = parse_iso8601_utc(line.substr(0, line.find(',')));
  EXPECT_TRUE(t.has_value()) << line;
  return t.value_or(UtcTime{});
}

// Shifts every frame stamp of a timestamps CSV by `days`; returns the new first and last stamp.
std::pair<UtcTime, UtcTime> shift_stamps(const fs::path& csv, int days) {
  auto lines = lines_of(test::read_text(csv));
  std::string out = lines[0] + "\n";
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const UtcTime t{utc_field(lines[i]).ns + days * 86400 * kNsPerSecond};
    out += lines[i].substr(0, lines[i].rfind(',') + 1) + format_iso8601_utc(t) + "\n";
  }
  test::write_text(csv, out);
  lines = lines_of(out);
  return {utc_field(lines[1]), utc_field(lines.back())};
}

TEST(AlignFailureCli, FrameStampsADayOffFailAlignWithBothSpansAndTheCameraClock) {
  const fs::path d = test::scratch_dir("align_day_off");
  test::write_text(d / "scenario.json", test::small_two_camera_scenario_text());
  const auto sim = test::run_cli("-q simulate " + q(d / "scenario.json") + " --out " + q(d / "mission"));
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const fs::path m = d / "mission";
  const auto c1 = shift_stamps(m / "c1/timestamps.csv", 1);
  const auto c2 = shift_stamps(m / "c2/timestamps.csv", 1);

  const auto r = test::run_cli("-q run " + q(m / "mission.json"));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_TRUE(r.err.find("internal error") == std::string::npos) << r.err;
  // The lamp track the gnss stage wrote, its span read here.
  const auto track = lines_of(test::read_text(m / "out/gnss/lamp_track.csv"));
  const UtcTime track_first = first_field_utc(track[1]), track_last = first_field_utc(track.back());
  // The tracks start on the mission day, the frames a day later.
  EXPECT_EQ(format_iso8601_utc(track_first, 0).substr(0, 10), "2026-05-14");
  EXPECT_EQ(format_iso8601_utc(c1.first, 0).substr(0, 10), "2026-05-15");
  for (const std::string& part :
       {std::string("no camera has a frame that aligns with the lamp track"),
        "lamp track " + format_iso8601_utc(track_first, 3) + " .. " + format_iso8601_utc(track_last, 3),
        "camera c1 frames " + format_iso8601_utc(c1.first, 3) + " .. " + format_iso8601_utc(c1.second, 3),
        "camera c2 frames " + format_iso8601_utc(c2.first, 3) + " .. " + format_iso8601_utc(c2.second, 3),
        std::string("camera clock not set (date)"), std::string("about 1 day(s)")})
    EXPECT_NE(r.err.find(part), std::string::npos) << "missing '" << part << "' in: " << r.err;

  const auto runlog = nlohmann::json::parse(test::read_text(m / "out/run.json"));
  EXPECT_EQ(runlog["status"], "failed");
  EXPECT_EQ(runlog["failed_stage"], "align");
  EXPECT_EQ(runlog["stages"]["gnss"]["status"], "ok");
  const auto& align = runlog["stages"]["align"];
  EXPECT_EQ(align["status"], "failed");
  EXPECT_EQ(align["error"]["exit_code"], 3);
  EXPECT_NE(align["error"]["message"].get<std::string>().find("camera clock not set"), std::string::npos);
  EXPECT_FALSE(runlog["stages"].contains("detect"));
  EXPECT_FALSE(fs::exists(m / "out/c1/aligned.csv"));

  // The align stage alone says the same.
  const auto alone = test::run_cli("-q align " + q(m / "mission.json"));
  EXPECT_EQ(alone.exit_code, 3);
  EXPECT_NE(alone.err.find("camera clock not set (date)"), std::string::npos) << alone.err;
}

}  // namespace
}  // namespace rangecal
