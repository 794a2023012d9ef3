// `rangecal trajectory CONFIG` (alias `track`) on missions that give it nothing to do or lack what it
// reads: a clear error or a partial outcome naming the cause, never exit 0 with an empty answer.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "support/paths.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

nlohmann::json mission(const fs::path& dir) {
  test::write_text(dir / "rover.pos", "% empty\n");
  test::write_text(dir / "target.csv", "frame,u,v\n1,100,100\n2,101,101\n");
  test::write_text(dir / "times.csv", "frame,utc\n1,2026-05-04T10:00:00Z\n2,2026-05-04T10:00:00.02Z\n");
  nlohmann::json j = {{"site", {{"origin", {{"lat", 45.6}, {"lon", 122.8}, {"h", 150.0}}}}},
                      {"gnss", {{"pos_files", {(dir / "rover.pos").string()}}}},
                      {"lever_arm", {{"vertical_m", 0.25}}},
                      {"output_dir", (dir / "out").string()}};
  for (const char* id : {"cam1", "cam2"})
    j["cameras"].push_back(
        {{"id", id},
         {"sensor", {{"width_px", 1280}, {"height_px", 800}, {"pixel_size_um", {20, 20}}}},
         {"lens", {{"nominal_focal_mm", 135}}},
         {"target_track",
          {{"file", (dir / "target.csv").string()}, {"timestamps", (dir / "times.csv").string()}}}});
  return j;
}

TEST(TrajectoryCli, NoTargetTrackIsAnInputError) {
  const fs::path dir = test::scratch_dir("trajectory_cli_none");
  nlohmann::json j = mission(dir);
  for (auto& cam : j["cameras"]) cam.erase("target_track");
  test::write_text(dir / "m.json", j.dump());
  const auto r = test::run_cli("trajectory '" + (dir / "m.json").string() + "'");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("cameras[].target_track"), std::string::npos) << r.err;
}

TEST(TrajectoryCli, UncalibratedCamerasMakeThePartialOutcomeNamingTheirFiles) {
  const fs::path dir = test::scratch_dir("trajectory_cli_uncalibrated");
  test::write_text(dir / "m.json", mission(dir).dump());
  const auto r = test::run_cli("track '" + (dir / "m.json").string() + "'");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.out.find("cam1/calibration.json"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("two calibrated cameras"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "trajectory.csv"));
}

}  // namespace
}  // namespace rangecal
