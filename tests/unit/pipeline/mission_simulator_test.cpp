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

#include "pipeline/mission/mission_config.hpp"
#include "support/paths.hpp"
#include "support/pos_rows.hpp"
#include "support/tiny_scenario.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kLat0 = 45.6, kLon0 = 122.8, kH0 = 150.0;

json tiny() {
  return test::tiny_scenario();
}

Scenario scenario_of(const json& j) {
  return parse_scenario(j.dump(), "tiny.json");
}

fs::path simulate_to(const json& j, const std::string& name) {
  const fs::path dir = test::scratch_dir(name);
  write_mission(simulate_mission(scenario_of(j)), dir.string());
  return dir;
}

json read_json(const fs::path& p) {
  return json::parse(test::read_text(p));
}

Eigen::Vector3d vec(const json& a) {
  return {a[0].get<double>(), a[1].get<double>(), a[2].get<double>()};
}

// Converts geodetic rows to ENU about the site origin with GeographicLib's CartConvert tool.
std::vector<Eigen::Vector3d> cartconvert(const std::vector<Eigen::Vector3d>& llh, const fs::path& dir) {
  const fs::path in = dir / "cartconvert_in.txt";
  std::string text;
  char b[128];
  for (const auto& p : llh) {
    std::snprintf(b, sizeof b, "%.12f %.12f %.6f\n", p[0], p[1], p[2]);
    text += b;
  }
  test::write_text(in, text);
  std::snprintf(b, sizeof b, "/usr/bin/CartConvert -p 9 -l %.9f %.9f %.4f < ", kLat0, kLon0, kH0);
  FILE* pipe = popen((std::string(b) + "'" + in.string() + "'").c_str(), "r");
  EXPECT_NE(pipe, nullptr);
  std::vector<Eigen::Vector3d> out;
  double x, y, z;
  while (pipe && std::fscanf(pipe, "%lf %lf %lf", &x, &y, &z) == 3) out.emplace_back(x, y, z);
  if (pipe) {
    EXPECT_EQ(pclose(pipe), 0);
  }
  return out;
}

// "2026-05-14T02:30:00.100000000Z" + seconds → "2026/05/14 02:30:18.100" with the C library.
std::string calendar_plus(const std::string& iso, int add_s) {
  std::tm tm{};
  int ns = 0;
  std::sscanf(iso.c_str(), "%d-%d-%dT%d:%d:%d.%dZ", &tm.tm_year, &tm.tm_mon, &tm.tm_mday, &tm.tm_hour,
              &tm.tm_min, &tm.tm_sec, &ns);
  tm.tm_year -= 1900;
  tm.tm_mon -= 1;
  const std::time_t t = timegm(&tm) + add_s;
  std::tm out{};
  gmtime_r(&t, &out);
  char b[64];
  std::strftime(b, sizeof b, "%Y/%m/%d %H:%M:%S", &out);
  char ms[8];
  std::snprintf(ms, sizeof ms, ".%03d", (ns + 500000) / 1000000);
  return std::string(b) + ms;
}

TEST(MissionSimulator, PosReproducesTruthThroughCartConvert) {
  const fs::path dir = simulate_to(tiny(), "sim_pos_cartconvert");
  const json truth = read_json(dir / "truth.json");
  const auto rows = test::pos_rows(dir / "gnss" / "rover.pos");
  ASSERT_EQ(rows.size(), truth["epochs"].size());
  ASSERT_GT(rows.size(), 30u);
  std::vector<Eigen::Vector3d> llh;
  for (const auto& r : rows) llh.emplace_back(std::stod(r[2]), std::stod(r[3]), std::stod(r[4]));
  const auto enu = cartconvert(llh, dir);
  ASSERT_EQ(enu.size(), rows.size());
  double worst = 0, worst_true = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const json& e = truth["epochs"][i];
    const Eigen::Vector3d d = enu[i] - vec(e["antenna_measured_enu_m"]);
    worst = std::max(worst, d.cwiseAbs().maxCoeff());
    worst_true = std::max(worst_true, (enu[i] - vec(e["antenna_true_enu_m"])).norm());
  }
  EXPECT_LT(worst, 1e-4);       // .pos rounding (1e-9 deg, 0.1 mm) only
  EXPECT_GT(worst_true, 0.01);  // the noise is really there (1 cm sd, tens of epochs)
}

TEST(MissionSimulator, NoiseFreePosIsTheTrueAntennaTrack) {
  json j = tiny();
  j["gnss"]["noise_sd_m"] = {0, 0, 0};
  const fs::path dir = simulate_to(j, "sim_pos_noise_free");
  const json truth = read_json(dir / "truth.json");
  const auto rows = test::pos_rows(dir / "gnss" / "rover.pos");
  std::vector<Eigen::Vector3d> llh;
  for (const auto& r : rows) llh.emplace_back(std::stod(r[2]), std::stod(r[3]), std::stod(r[4]));
  const auto enu = cartconvert(llh, dir);
  ASSERT_EQ(enu.size(), truth["epochs"].size());
  for (std::size_t i = 0; i < enu.size(); ++i) {
    const Eigen::Vector3d t = vec(truth["epochs"][i]["antenna_true_enu_m"]);
    EXPECT_LT((enu[i] - t).cwiseAbs().maxCoeff(), 1e-4) << i;
  }
  // The ascent really is in the file: from 1.5 m to 4.5 m up, at E = N = 0.
  EXPECT_NEAR(enu.front().z(), 1.5, 1e-4);
  EXPECT_NEAR(enu.back().z(), 4.5, 1e-4);
}

TEST(MissionSimulator, PosTimesAreGpstUtcPlus18) {
  const fs::path dir = simulate_to(tiny(), "sim_pos_gpst");
  const json truth = read_json(dir / "truth.json");
  const auto rows = test::pos_rows(dir / "gnss" / "rover.pos");
  ASSERT_EQ(rows.size(), truth["epochs"].size());
  for (std::size_t i = 0; i < rows.size(); ++i)
    EXPECT_EQ(rows[i][0] + " " + rows[i][1], calendar_plus(truth["epochs"][i]["utc"].get<std::string>(), 18));
  EXPECT_EQ(rows[0][0] + " " + rows[0][1], "2026/05/14 02:30:18.000");
  EXPECT_NE(test::read_text(dir / "gnss" / "rover.pos").find("%  GPST "), std::string::npos);
}

// R_nb = Rz(yaw)·Ry(pitch)·Rx(roll), written out element by element (docs/conventions.md).
Eigen::Matrix3d hand_rnb(double roll_deg, double pitch_deg, double yaw_deg) {
  const double r = roll_deg * M_PI / 180, p = pitch_deg * M_PI / 180, y = yaw_deg * M_PI / 180;
  const double cr = std::cos(r), sr = std::sin(r), cp = std::cos(p), sp = std::sin(p), cy = std::cos(y),
               sy = std::sin(y);
  Eigen::Matrix3d R;
  R << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  return R;
}

TEST(MissionSimulator, LeverArmHandCaseYaw90) {
  json j = tiny();
  j["attitude"] = {{"wobble_deg", 0}, {"yaw_deg", 90}, {"tilt_with_acceleration", false}};
  j["lever_arm"]["body_frd_m"] = {0.3, 0.2, 0.25};
  const fs::path dir = simulate_to(j, "sim_lever_yaw90");
  const json truth = read_json(dir / "truth.json");
  // Heading east: forward 0.3 → east, right 0.2 → south, down 0.25 → −U.
  for (const json& e : truth["epochs"]) {
    const Eigen::Vector3d d = vec(e["lamp_true_enu_m"]) - vec(e["antenna_true_enu_m"]);
    EXPECT_LT((d - Eigen::Vector3d(0.3, -0.2, -0.25)).norm(), 1e-12);
  }
}

TEST(MissionSimulator, LeverArmWithWobbleMatchesHandRotation) {
  json j = tiny();
  j["lever_arm"]["body_frd_m"] = {0.3, -0.1, 0.25};
  const fs::path dir = simulate_to(j, "sim_lever_wobble");
  const json truth = read_json(dir / "truth.json");
  double max_tilt = 0;
  for (const json& e : truth["epochs"]) {
    const auto& a = e["attitude_deg"];
    const Eigen::Vector3d ned = hand_rnb(a[0], a[1], a[2]) * Eigen::Vector3d(0.3, -0.1, 0.25);
    const Eigen::Vector3d expect = vec(e["antenna_true_enu_m"]) + Eigen::Vector3d(ned[1], ned[0], -ned[2]);
    EXPECT_LT((vec(e["lamp_true_enu_m"]) - expect).norm(), 1e-12);
    max_tilt = std::max({max_tilt, std::abs(a[0].get<double>()), std::abs(a[1].get<double>())});
  }
  EXPECT_GT(max_tilt, 0.3);  // the wobble is there
  EXPECT_LT(max_tilt, 3.0);
  // The attitude CSV carries the same angles at the epochs (50 Hz log, 10 Hz epochs share instants).
  const std::string att = test::read_text(dir / "gnss" / "attitude.csv");
  EXPECT_EQ(att.rfind("utc,roll_deg,pitch_deg,yaw_deg\n", 0), 0u);
  const std::string t1 = truth["epochs"][3]["utc"].get<std::string>().substr(0, 26) + "Z,";
  const auto pos = att.find(t1);
  ASSERT_NE(pos, std::string::npos) << t1;
  double r, p, y;
  ASSERT_EQ(std::sscanf(att.c_str() + pos + t1.size(), "%lf,%lf,%lf", &r, &p, &y), 3);
  EXPECT_NEAR(r, truth["epochs"][3]["attitude_deg"][0].get<double>(), 1e-6);
  EXPECT_NEAR(y, truth["epochs"][3]["attitude_deg"][2].get<double>(), 1e-6);
}

TEST(MissionSimulator, FramePixelIsTheHandPinholeAndTheRenderedSpot) {
  json j = tiny();
  j["attitude"]["wobble_deg"] = 0.5;
  const fs::path dir = simulate_to(j, "sim_pixels");
  const json truth = read_json(dir / "truth.json");
  const json& cam = truth["cameras"][0];
  // Camera at (0, −30, 3) looking north, k1 = 0: Xc = (E, 3 − U, N + 30).
  const double f = 25, dx = 0.020, sx = 1.01, u0 = 101.5, v0 = 73.25;
  int checked = 0;
  for (const json& fr : cam["frames"]) {
    if (!fr["in_view"].get<bool>()) continue;
    const Eigen::Vector3d X = vec(fr["lamp_enu_m"]);
    const Eigen::Vector3d Xc(X.x(), 3 - X.z(), X.y() + 30);
    const double u = u0 + sx * f * Xc.x() / Xc.z() / dx, v = v0 + f * Xc.y() / Xc.z() / dx;
    EXPECT_NEAR(fr["lamp_px"][0].get<double>(), u, 1e-6);
    EXPECT_NEAR(fr["lamp_px"][1].get<double>(), v, 1e-6);
    // The rendered frame: the brightest pixel, then the background-subtracted centroid of its
    // 7×7 neighbourhood, sits at the truth pixel.
    const cv::Mat img =
        cv::imread((dir / "c1" / fr["file"].get<std::string>()).string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(img.type(), CV_16UC1);
    ASSERT_EQ(img.cols, 200);
    if (u < 4 || v < 4 || u > 195 || v > 145) continue;
    cv::Point mx;
    cv::minMaxLoc(img, nullptr, nullptr, nullptr, &mx);
    EXPECT_LE(std::abs(mx.x - u), 1.0);
    EXPECT_LE(std::abs(mx.y - v), 1.0);
    double sw = 0, su = 0, sv = 0;
    for (int y = mx.y - 3; y <= mx.y + 3; ++y)
      for (int x = mx.x - 3; x <= mx.x + 3; ++x) {
        const double w =
            std::max(0.0, img.at<std::uint16_t>(y, x) - (1000 + 0.5 * (x - 100) - 0.5 * (y - 75)));
        sw += w;
        su += w * x;
        sv += w * y;
      }
    EXPECT_NEAR(su / sw, u, 0.5);
    EXPECT_NEAR(sv / sw, v, 0.5);
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

TEST(MissionSimulator, FramesExportedEveryStepWithUtcStamps) {
  const fs::path dir = simulate_to(tiny(), "sim_export");
  const std::string csv = test::read_text(dir / "c1" / "timestamps.csv");
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "frame,file,utc");
  std::int64_t expect_frame = 0;
  int n = 0;
  while (std::getline(in, line)) {
    long long frame;
    char file[128], utc[64];
    ASSERT_EQ(std::sscanf(line.c_str(), "%lld,%127[^,],%63s", &frame, file, utc), 3) << line;
    EXPECT_EQ(frame, expect_frame);
    EXPECT_TRUE(fs::is_regular_file(dir / "c1" / file)) << file;
    // stamp = start + frame/100 s + 0.0021 s, by hand.
    const long long ns_total = frame * 10000000LL + 2100000LL;
    const std::time_t secs = 1778725800 + ns_total / 1000000000LL;
    std::tm tm{};
    gmtime_r(&secs, &tm);
    char b[64];
    std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%S", &tm);
    char frac[16];
    std::snprintf(frac, sizeof frac, ".%09lldZ", ns_total % 1000000000LL);
    EXPECT_EQ(std::string(utc), std::string(b) + frac);
    expect_frame += 5;
    ++n;
  }
  // Flight: hover 0.5 s + 3 m at 2 m/s with 2 m/s² (1 s up to speed, 0.5 s cruise, 1 s down) +
  // hover 0.5 s = 3.5 s → frames 0…350 by 5.
  EXPECT_EQ(n, 71);
  std::size_t pngs = 0;
  for (const auto& e : fs::directory_iterator(dir / "c1" / "frames")) pngs += e.path().extension() == ".png";
  EXPECT_EQ(pngs, 71u);
}

TEST(MissionSimulator, GapsAndFloatEpochs) {
  json j = tiny();
  j["gnss"]["gaps"] = {{1.0, 1.45}};
  j["gnss"]["float_intervals"] = {{2.0, 2.25}};
  j["gnss"]["float_noise_factor"] = 10;
  const fs::path dir = simulate_to(j, "sim_gaps");
  const auto rows = test::pos_rows(dir / "gnss" / "rover.pos");
  int floats = 0;
  for (const auto& r : rows) {
    const double sec = std::stod(r[1].substr(6));  // seconds within the minute (GPST 02:30:18 + t)
    const double t = sec - 18.0;
    EXPECT_FALSE(t > 0.999 && t < 1.451) << r[1];
    const bool in_float = t > 1.999 && t < 2.251;
    EXPECT_EQ(r[5], in_float ? "2" : "1") << r[1];
    EXPECT_EQ(r[9], in_float ? "0.1500" : "0.0150") << r[1];  // sdu
    floats += in_float;
  }
  EXPECT_EQ(floats, 3);
  EXPECT_EQ(rows.size(), 36u - 5u);  // 0.0 … 3.5 s at 10 Hz, minus 1.0 … 1.4
}

TEST(MissionSimulator, PolesAndPicks) {
  json j = tiny();
  j["pick_noise_px"] = 0;
  const fs::path dir = simulate_to(j, "sim_poles");
  const json truth = read_json(dir / "truth.json");
  // poles.csv (lat, lon, h) through CartConvert = the surveyed positions; survey noise present.
  std::istringstream in(test::read_text(dir / "survey" / "poles.csv"));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "id,role,lat,lon,h");
  std::vector<Eigen::Vector3d> llh;
  std::vector<std::string> ids;
  while (std::getline(in, line)) {
    char id[32], role[32];
    double a, b, c;
    ASSERT_EQ(std::sscanf(line.c_str(), "%31[^,],%31[^,],%lf,%lf,%lf", id, role, &a, &b, &c), 5);
    ids.push_back(id);
    llh.emplace_back(a, b, c);
  }
  ASSERT_EQ(ids.size(), 3u);
  const auto enu = cartconvert(llh, dir);
  ASSERT_EQ(enu.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const json& p = truth["poles"][i];
    EXPECT_EQ(p["id"], ids[i]);
    EXPECT_LT((enu[i] - vec(p["surveyed_enu_m"])).cwiseAbs().maxCoeff(), 1e-4);
    const double err = (vec(p["surveyed_enu_m"]) - vec(p["true_enu_m"])).norm();
    EXPECT_GT(err, 1e-5);
    EXPECT_LT(err, 0.004 * 6);
  }
  // Picks: only the two poles in view, at the hand pinhole pixel (pick noise 0 here).
  EXPECT_EQ(test::read_text(dir / "c1" / "poles_px.csv"), [] {
    auto px = [](double E, double N, double U) {
      char b[64];
      std::snprintf(b, sizeof b, "%.3f,%.3f", 101.5 + 1.01 * 25 * E / (N + 30) / 0.02,
                    73.25 + 25 * (3 - U) / (N + 30) / 0.02);
      return std::string(b);
    };
    return "id,u,v\nP1," + px(0.5, 1.0, 3.2) + "\nP2," + px(-0.8, -1.0, 2.1) + "\n";
  }());
}

TEST(MissionSimulator, SameSeedSameBytesOtherSeedOtherNoise) {
  const fs::path a = simulate_to(tiny(), "sim_det_a");
  const fs::path b = simulate_to(tiny(), "sim_det_b");
  std::size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(a)) {
    if (!e.is_regular_file()) continue;
    const fs::path rel = fs::relative(e.path(), a);
    ASSERT_TRUE(fs::exists(b / rel)) << rel;
    EXPECT_EQ(test::read_text(e.path()), test::read_text(b / rel)) << rel;
    ++files;
  }
  EXPECT_GT(files, 60u);
  json j = tiny();
  j["seed"] = 12;
  const fs::path c = simulate_to(j, "sim_det_c");
  EXPECT_NE(test::read_text(a / "gnss" / "rover.pos"), test::read_text(c / "gnss" / "rover.pos"));
  EXPECT_NE(test::read_text(a / "c1" / "frames" / "c1_0000100.png"),
            test::read_text(c / "c1" / "frames" / "c1_0000100.png"));
}

TEST(MissionSimulator, WrittenMissionConfigLoads) {
  const fs::path dir = simulate_to(tiny(), "sim_config");
  const MissionConfig cfg = load_mission_config((dir / "mission.json").string());
  ASSERT_EQ(cfg.cameras.size(), 1u);
  EXPECT_EQ(cfg.cameras[0].id, "c1");
  EXPECT_EQ(fs::path(cfg.gnss.pos_files.at(0)), dir / "gnss" / "rover.pos");
  EXPECT_EQ(fs::path(cfg.attitude_file), dir / "gnss" / "attitude.csv");
  EXPECT_EQ(fs::path(cfg.poles_file), dir / "survey" / "poles.csv");
  EXPECT_EQ(fs::path(cfg.cameras[0].frames.timestamps), dir / "c1" / "timestamps.csv");
  EXPECT_EQ(cfg.lever_arm.kind, LeverArmConfig::Kind::body_frd);
  EXPECT_DOUBLE_EQ(cfg.lever_arm.body_frd_m.z(), 0.25);
  EXPECT_EQ(cfg.cameras[0].sensor.width_px, 200);
  EXPECT_DOUBLE_EQ(cfg.origin.lat_deg, kLat0);
  EXPECT_DOUBLE_EQ(cfg.cameras[0].nominal_focal_mm, 25.0);
}

TEST(MissionSimulator, SpeedProfileByHand) {
  json j = tiny();
  // Route 1: vertical 3 m (speed 2, accel 2: 1 s up to speed, 0.5 s cruise, 1 s down), hovers 0.5 s.
  // Route 2: a 1 m line at speed 2, accel 1 — too short to reach 2 m/s: triangular, peak 1 m/s, 2 s.
  // Transit between them: from (0, 0, 4.5) to (−1, 0, 3.5), √2 m at 3 m/s, 1 m/s² → peak √√2, 2·2^¼ s.
  j["routes"].push_back({{"type", "line"},
                         {"start_enu_m", {-1, 0, 3.5}},
                         {"end_enu_m", {0, 0, 3.5}},
                         {"speed_mps", 2},
                         {"accel_mps2", 1},
                         {"hover_s", 0}});
  j["transit"] = {{"speed_mps", 3}, {"accel_mps2", 1}};
  const Scenario s = scenario_of(j);
  const FlightPath plan = make_flight_path(s);
  ASSERT_EQ(plan.legs.size(), 5u);  // hover, ascent, hover, transit, line
  const double tt = 2 * std::pow(2.0, 0.25);
  EXPECT_NEAR(plan.legs[3].t1_s - plan.legs[3].t0_s, tt, 1e-12);
  EXPECT_NEAR(plan.duration_s(), 3.5 + tt + 2.0, 1e-12);
  auto at = [&](double t) { return state_at(s, plan, t).antenna_enu; };
  EXPECT_LT((at(0.25) - Eigen::Vector3d(0, 0, 1.5)).norm(), 1e-12);
  EXPECT_LT((at(1.0) - Eigen::Vector3d(0, 0, 1.75)).norm(), 1e-12);  // ½·2·0.5²
  EXPECT_LT((at(1.75) - Eigen::Vector3d(0, 0, 3.0)).norm(), 1e-12);  // 1 + 2·0.25, mid-route
  EXPECT_LT((at(2.5) - Eigen::Vector3d(0, 0, 4.25)).norm(), 1e-12);  // 1.5 + 3 − ½·2·0.5²
  EXPECT_LT((at(3.2) - Eigen::Vector3d(0, 0, 4.5)).norm(), 1e-12);   // hovering at the top
  const double t_line = 3.5 + tt;
  EXPECT_LT((at(t_line + 1.0) - Eigen::Vector3d(-0.5, 0, 3.5)).norm(), 1e-12);  // half way, at peak
  EXPECT_LT((at(t_line + 0.5) - Eigen::Vector3d(-0.875, 0, 3.5)).norm(), 1e-12);
  EXPECT_NEAR(state_at(s, plan, t_line + 1.0).velocity_enu.x(), 1.0, 1e-12);
  EXPECT_LT((at(1e3) - Eigen::Vector3d(0, 0, 3.5)).norm(), 1e-12);  // clamped to the end
}

TEST(MissionSimulator, SkyHotPixelsDistractorSaturationAndEightBit) {
  json j = tiny();
  j["sky"] = {{"background", 1000},
              {"read_noise", 10},
              {"hot_pixels", 3},
              {"hot_pixel_excess", 20000},
              {"distractor", {{"u", 50.0}, {"v", 40.0}, {"peak", 10000}, {"sigma_px", 1.0}}}};
  j["lamp"] = {{"psf_sigma_px", 1.0}, {"peak", 30000}, {"saturation", 12000}};
  const SimMission m = simulate_mission(scenario_of(j));
  const SimCamera& c = m.cameras[0];
  ASSERT_EQ(c.hot_pixels.size(), 3u);
  int lamp_frames = 0;
  for (std::size_t k : {std::size_t(10), std::size_t(30)}) {
    const SimFrame& f = c.frames[k];
    const cv::Mat img = render_sim_frame(m, c, f);
    ASSERT_EQ(img.type(), CV_16UC1);
    for (const HotPixel& h : c.hot_pixels) {
      EXPECT_GE(h.excess, 10000);
      EXPECT_LE(h.excess, 20000);
      EXPECT_GT(img.at<std::uint16_t>(h.v, h.u), 1000 + 10000 - 60);
    }
    // Pixel-integrated unit Gaussian centred on a pixel: (erf(0.5/√2))² = 0.1466 of 2π·peak.
    EXPECT_NEAR(img.at<std::uint16_t>(40, 50), 1000 + 10000 * 2 * M_PI * 0.146631, 60);
    EXPECT_NEAR(cv::mean(img(cv::Rect(0, 100, 20, 20)))[0], 1000, 3);  // sky far from everything
    double mx;
    cv::minMaxLoc(img, nullptr, &mx);
    EXPECT_LE(mx, 12000);  // lamp.saturation clips
    if (f.in_view) {
      EXPECT_EQ(mx, 12000);
      ++lamp_frames;
    }
  }
  EXPECT_GT(lamp_frames, 0);
  j["cameras"][0]["bit_depth"] = 8;
  const SimMission m8 = simulate_mission(scenario_of(j));
  const cv::Mat img8 = render_sim_frame(m8, m8.cameras[0], m8.cameras[0].frames[10]);
  ASSERT_EQ(img8.type(), CV_8UC1);
  EXPECT_NEAR(cv::mean(img8(cv::Rect(0, 100, 20, 20)))[0], 1000 * 255.0 / 65535, 0.5);
}

TEST(MissionSimulator, DemoScenarioGeometry) {
  const auto path = test::source_dir() / "config" / "examples" / "seed002_scenario.json";
  const SimMission m = simulate_mission(load_scenario(path.string()));
  ASSERT_EQ(m.cameras.size(), 2u);
  for (const SimCamera& c : m.cameras) {
    std::size_t in_view = 0;
    for (const SimFrame& f : c.frames) in_view += f.in_view;
    EXPECT_GT(in_view, 60u) << c.spec.id;                    // plenty of lamp observations per camera
    EXPECT_LT(in_view, c.frames.size()) << c.spec.id;        // and frames without the lamp
    EXPECT_EQ(c.picks.size(), m.poles.size()) << c.spec.id;  // every pole in both views
    EXPECT_EQ(c.hot_pixels.size(), 20u);
  }
  std::size_t floats = 0;
  for (const SimEpoch& e : m.epochs) floats += e.quality == 2;
  EXPECT_GT(floats, 3u);
  EXPECT_GT(m.path.duration_s(), 20);
  EXPECT_LT(m.path.duration_s(), 60);
}

}  // namespace
}  // namespace rangecal
