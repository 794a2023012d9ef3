// The simulator's written files against independent computations: GeographicLib's CartConvert
// (run as a separate program) for the .pos geodesy, the C library's calendar for GPST = UTC + 18 s,
// hand-written lever-arm rotations and pinhole projections, the rendered pixels themselves; plus
// export decimation, gaps and float epochs, determinism, and the written mission config.
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

#include "pipeline/config/mission_config.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kLat0 = 45.6, kLon0 = 122.8, kH0 = 150.0;

// One camera looking north at a 4 m vertical ascent 30 m away; 200×150 px frames at 100 fps,
// every 5th exported.
json tiny() {
  return json::parse(R"({
    "seed": 11,
    "start_utc": "2026-05-14T02:30:00Z",
    "site": {"origin": {"lat": 45.6, "lon": 122.8, "h": 150.0}},
    "gnss": {"rate_hz": 10, "noise_sd_m": [0.01, 0.01, 0.015]},
    "lever_arm": {"body_frd_m": [0.0, 0.0, 0.25]},
    "attitude": {"rate_hz": 50, "wobble_deg": 1.5, "yaw_deg": 30},
    "lamp": {"psf_sigma_px": 1.2, "peak": 20000},
    "sky": {"background": 1000, "gradient": [0.5, -0.5], "read_noise": 30},
    "cameras": [{"id": "c1", "center_enu_m": [0, -30, 3], "look_at_enu_m": [0, 0, 3], "f_mm": 25,
                 "pixel_size_um": 20, "width_px": 200, "height_px": 150, "u0_px": 101.5, "v0_px": 73.25,
                 "sx": 1.01, "fps": 100, "export_step": 5, "clock_offset_s": 0.0021}],
    "routes": [{"type": "vertical", "start_enu_m": [0, 0, 1.5], "height_m": 3, "speed_mps": 2,
                "accel_mps2": 2, "hover_s": 0.5}],
    "poles": [{"id": "P1", "role": "control", "enu_m": [0.5, 1.0, 3.2]},
              {"id": "P2", "role": "check", "enu_m": [-0.8, -1.0, 2.1]},
              {"id": "FAR", "role": "check", "enu_m": [40, 0, 2]}],
    "survey_noise_m": 0.004,
    "pick_noise_px": 0.2
  })");
}

TEST(MissionSimulator, CliSimulateWritesAndRejects) {
  const fs::path dir = test::scratch_dir("sim_cli");
  test::write_text(dir / "tiny.json", tiny().dump(2));
  const auto ok =
      test::run_cli("simulate '" + (dir / "tiny.json").string() + "' --out '" + (dir / "out").string() + "'");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("71 frames"), std::string::npos) << ok.out;
  EXPECT_TRUE(fs::is_regular_file(dir / "out" / "mission.json"));
  json bad = tiny();
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
