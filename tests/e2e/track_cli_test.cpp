// Cameras with imported 2-D tracks and no time code, through the CLI (docs/formats.md "Imported tracks",
// docs/alignment.md "Cameras without time code"): the demo's scenario simulated (20 fps exported), each
// camera's lamp pixels taken from the simulator's truth (truth.json) with 0.3 px of noise and written as a
// track whose nominal frame times are 40 s early and run 1e-4 slow; rangecal's gnss, align, detect and
// calibrate stages find each clock within 4σ (its σ carrying the fixes' correlated error along the
// lamp's path) and calibrate each camera within 4σ of the simulated truth. A track in a format rangecal does
// not know is refused naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>

#include "config/deterministic_random.hpp"
#include "gnss/time/utc_time.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kOffsetS = 40.0, kRate = 1e-4;

json read_json(const fs::path& p) {
  return json::parse(test::read_text(p));
}

double seconds(const std::string& utc) {
  return 1e-9 * static_cast<double>(parse_iso8601_utc(utc)->ns);
}

// Writes <cam>/track.csv and <cam>/nominal_times.csv from truth.json's frames; returns each labelled
// frame's (nominal, true) time (s).
std::vector<std::pair<double, double>> write_track(const json& cam, const fs::path& dir,
                                                   DeterministicRandom* rng) {
  std::vector<std::pair<double, double>> labelled;
  fs::create_directories(dir);
  std::ofstream track(dir / "track.csv"), times(dir / "nominal_times.csv");
  track << "frame,u,v,sigma_px\n";
  times << "frame,utc\n";
  double first = NAN;
  for (const json& f : cam["frames"]) {
    const double truth = seconds(f["true_utc"].get<std::string>());
    if (std::isnan(first)) first = truth;
    // nominal = first − offset + (truth − first)/(1 + rate): the clock to find is (offset, rate).
    const double nominal = first - kOffsetS + (truth - first) / (1 + kRate);
    times << f["frame"].get<long>() << "," << format_iso8601_utc(UtcTime{std::llround(nominal * 1e9)})
          << "\n";
    if (!f["in_view"].get<bool>() || f["lamp_px"].is_null()) continue;
    labelled.emplace_back(nominal, truth);
    track << f["frame"].get<long>() << "," << std::setprecision(10)
          << f["lamp_px"][0].get<double>() + 0.3 * rng->normal() << ","
          << f["lamp_px"][1].get<double>() + 0.3 * rng->normal() << ","
          << (labelled.size() % 10 == 0 ? "0.3" : "") << "\n";  // every 10th label states its σ
  }
  return labelled;
}

TEST(ImportedTracks, CamerasWithoutTimeCodeCalibrate) {
  const fs::path dir = test::scratch_dir("track_cli");
  // The demo's scenario with every 25th frame of 500 fps exported (20 fps, as a consumer camera's
  // track), not every 100th: over its 26.6 s, 5 labels a second leave the rate ±100–140 ppm.
  json scenario = read_json(test::source_dir() / "config/examples/demo_scenario.json");
  for (json& cam : scenario["cameras"]) cam["export_step"] = 25;
  test::write_text(dir / "scenario.json", scenario.dump(2));
  const auto sim = test::run_cli("simulate '" + (dir / "scenario.json").string() + "' --out '" +
                                 (dir / "sim").string() + "'");
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const json truth = read_json(dir / "sim" / "truth.json");
  json mission = read_json(dir / "sim" / "mission.json");
  DeterministicRandom rng(35);
  std::vector<std::vector<std::pair<double, double>>> labelled;
  for (std::size_t c = 0; c < mission["cameras"].size(); ++c) {
    json& cam = mission["cameras"][c];
    const std::string id = cam["id"];
    labelled.push_back(write_track(truth["cameras"][c], dir / "tracks" / id, &rng));
    cam.erase("frames");
    cam["track"] = {{"file", (dir / "tracks" / id / "track.csv").string()},
                    {"timestamps", (dir / "tracks" / id / "nominal_times.csv").string()},
                    {"clock", "estimate"}};
  }
  mission["calibrate"] = {{"method", "bundle"}, {"free", {"f", "k1", "u0", "v0", "pose"}}};
  mission["output_dir"] = (dir / "out").string();
  test::write_text(dir / "sim" / "tracks.json", mission.dump(2));
  for (const char* stage : {"gnss", "align", "detect", "calibrate"}) {
    const auto r = test::run_cli(std::string(stage) + " '" + (dir / "sim" / "tracks.json").string() + "'");
    ASSERT_EQ(r.exit_code, 0) << stage << ": " << r.err << r.out;
  }
  const json run = read_json(dir / "out" / "run.json");
  for (std::size_t c = 0; c < mission["cameras"].size(); ++c) {
    const std::string id = mission["cameras"][c]["id"];
    const json& clock = run["stages"]["align"]["counts"][id]["clock"];
    const json& tc = truth["cameras"][c];
    // The clock found puts every labelled frame within 2 ms of its true time.
    const double n0 = seconds(clock["nominal_start_utc"].get<std::string>());
    double worst = 0;
    for (const auto& [nominal, t] : labelled[c])
      worst = std::max(worst, std::abs(nominal + clock["offset_s"].get<double>() +
                                       1e-6 * clock["rate_ppm"].get<double>() * (nominal - n0) - t));
    std::printf("%s: offset %+.2f ms off (σ %.2f), rate %+.1f ppm off (σ %.1f), worst frame %.2f ms\n",
                id.c_str(), 1e3 * (clock["offset_s"].get<double>() - kOffsetS),
                1e3 * clock["offset_sd_s"].get<double>(), clock["rate_ppm"].get<double>() - 1e6 * kRate,
                clock["rate_sd_ppm"].get<double>(), 1e3 * worst);
    // Not the 2 ms of the unit test (tests/unit/pipeline/camera_clock_test.cpp, a white lamp track):
    // the demo's fixes carry a PPK error correlated over 30 s (0.8 / 1.4 cm), which moves the lamp
    // along its path by milliseconds at 2.5 m/s; the clock's σ carries it (track_sd_s).
    EXPECT_LT(worst, 4 * clock["offset_sd_s"].get<double>()) << id;
    EXPECT_GT(clock["track_sd_s"].get<double>(), 0) << id;
    EXPECT_LT(std::abs(clock["offset_s"].get<double>() - kOffsetS), 4 * clock["offset_sd_s"].get<double>())
        << id;
    EXPECT_LT(std::abs(clock["rate_ppm"].get<double>() - 1e6 * kRate), 4 * clock["rate_sd_ppm"].get<double>())
        << id << " rate " << clock["rate_ppm"] << " ± " << clock["rate_sd_ppm"];
    EXPECT_EQ(run["stages"]["align"]["counts"][id]["time_source"], "track timestamps CSV + estimated clock");
    // The labels that state their σ carry it to correspondences.csv; the others leave it blank.
    const std::string corr = test::read_text(dir / "out" / id / "correspondences.csv");
    EXPECT_NE(corr.find(",pixel_sigma_px\n"), std::string::npos) << id;
    EXPECT_NE(corr.find(",0.3000\n"), std::string::npos) << id;
    const json cal = read_json(dir / "out" / id / "calibration.json");
    const double f = cal["focal_mm"].get<double>(), sd = cal["sigma"]["focal_mm"].get<double>();
    EXPECT_LT(std::abs(f - tc["focal_mm"].get<double>()), 4 * sd) << id << " f " << f << " ± " << sd;
  }
  // A file that is no track.
  mission["cameras"][0]["track"]["file"] = (dir / "sim" / "mission.json").string();
  test::write_text(dir / "sim" / "bad.json", mission.dump(2));
  const auto bad = test::run_cli("align '" + (dir / "sim" / "bad.json").string() + "'");
  EXPECT_EQ(bad.exit_code, 3);
  EXPECT_NE(bad.err.find("mission.json:1"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("not a 2-D track file"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace rangecal
