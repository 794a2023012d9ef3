// Scenario JSON → Scenario: defaults, the look-at pose against a hand computation, and every kind
// of bad scenario naming its JSON path.
#include "pipeline/simulate/scenario.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "config/error.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

// A small valid scenario: one camera looking north at a vertical ascent 30 m away.
nlohmann::json tiny() {
  return nlohmann::json::parse(R"({
    "seed": 7,
    "start_utc": "2026-05-14T02:30:00Z",
    "site": {"origin": {"lat": 45.6, "lon": 122.8, "h": 150.0}},
    "cameras": [{"id": "c1", "center_enu_m": [0, -30, 3], "look_at_enu_m": [0, 0, 3], "f_mm": 25,
                 "pixel_size_um": 20, "width_px": 200, "height_px": 150}],
    "routes": [{"type": "vertical", "start_enu_m": [0, 0, 1], "height_m": 4}]
  })");
}

Error parse_error(const nlohmann::json& j) {
  try {
    parse_scenario(j.dump(), "scn.json");
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error for " << j.dump();
  return Error(ErrorKind::input, "", 0, "", "");
}

TEST(Scenario, TinyScenarioDefaultsAndPose) {
  const Scenario s = parse_scenario(tiny().dump(), "scn.json");
  EXPECT_EQ(s.seed, 7u);
  ASSERT_EQ(s.cameras.size(), 1u);
  const Camera& c = s.cameras[0].camera;
  EXPECT_DOUBLE_EQ(c.intr.dx_mm, 0.020);
  EXPECT_DOUBLE_EQ(c.intr.u0_px, 100.0);  // default: image centre
  EXPECT_DOUBLE_EQ(c.intr.v0_px, 75.0);
  EXPECT_EQ(s.cameras[0].export_step, 50);
  EXPECT_EQ(s.cameras[0].bit_depth, 16);
  // Looking north: camera x = east, y = down, z = north (by hand).
  Eigen::Matrix3d R;
  R << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  EXPECT_LT((c.pose.R - R).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((c.pose.center() - Eigen::Vector3d(0, -30, 3)).norm(), 1e-12);
  ASSERT_EQ(s.routes.size(), 1u);
  EXPECT_EQ(s.routes[0].end_enu_m, Eigen::Vector3d(0, 0, 5));
  EXPECT_EQ(s.start_utc.ns, 1778725800LL * 1000000000LL);  // date -u -d 2026-05-14T02:30:00Z +%s
}

TEST(Scenario, RollAboutTheOpticalAxis) {
  auto j = tiny();
  j["cameras"][0]["roll_deg"] = 90;
  const Scenario s = parse_scenario(j.dump(), "scn.json");
  // Rolled 90°: image x (right) now points down in the world, image y (down) west.
  Eigen::Matrix3d R;
  R << 0, 0, -1, -1, 0, 0, 0, 1, 0;
  EXPECT_LT((s.cameras[0].camera.pose.R - R).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Scenario, ExplicitRotation) {
  auto j = tiny();
  j["cameras"][0].erase("look_at_enu_m");
  j["cameras"][0]["R"] = {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}};
  const Scenario s = parse_scenario(j.dump(), "scn.json");
  EXPECT_DOUBLE_EQ(s.cameras[0].camera.pose.R(2, 1), 1.0);
  j["cameras"][0]["R"] = {{1, 0, 0}, {0, 1, 0}, {0, 1, 0}};
  EXPECT_EQ(parse_error(j).field(), "cameras[0].R");
}

TEST(Scenario, UnknownKeyNamesItsPath) {
  auto j = tiny();
  j["cameras"][0]["fmm"] = 25;
  const Error e = parse_error(j);
  EXPECT_EQ(e.field(), "cameras[0].fmm");
  EXPECT_NE(e.reason().find("f_mm"), std::string::npos) << e.reason();  // did you mean
  EXPECT_EQ(e.file(), "scn.json");
  EXPECT_EQ(e.exit_code(), 2);
  auto k = tiny();
  k["gnss"] = {{"rate", 10}};
  EXPECT_EQ(parse_error(k).field(), "gnss.rate");
  auto t = tiny();
  t["colour"] = 1;
  EXPECT_EQ(parse_error(t).field(), "colour");
}

TEST(Scenario, WrongTypeNamesItsPath) {
  auto j = tiny();
  j["gnss"] = {{"rate_hz", "ten"}};
  Error e = parse_error(j);
  EXPECT_EQ(e.field(), "gnss.rate_hz");
  EXPECT_NE(e.reason().find("the string \"ten\""), std::string::npos) << e.reason();
  auto k = tiny();
  k["routes"][0]["start_enu_m"] = {0, 0};
  EXPECT_EQ(parse_error(k).field(), "routes[0].start_enu_m");
  auto b = tiny();
  b["cameras"][0]["bit_depth"] = 12;
  EXPECT_EQ(parse_error(b).field(), "cameras[0].bit_depth");
  auto r = tiny();
  r["poles"] = {{{"id", "P1"}, {"role", "survey"}, {"enu_m", {0, 0, 1}}}};
  EXPECT_EQ(parse_error(r).field(), "poles[0].role");
}

TEST(Scenario, MissingAndImpossibleValues) {
  auto j = tiny();
  j.erase("start_utc");
  EXPECT_EQ(parse_error(j).field(), "start_utc");
  auto t = tiny();
  t["start_utc"] = "2026-05-14 25:00:00Z";
  EXPECT_EQ(parse_error(t).field(), "start_utc");
  auto v = tiny();
  v["routes"][0].erase("height_m");
  v["routes"][0]["end_enu_m"] = {1, 0, 5};  // a vertical route that moves sideways
  EXPECT_EQ(parse_error(v).field(), "routes[0].end_enu_m");
  auto g = tiny();
  g["gnss"] = {{"gaps", {{3.0, 2.0}}}};
  EXPECT_EQ(parse_error(g).field(), "gnss.gaps[0]");
  auto d = tiny();
  d["cameras"].push_back(d["cameras"][0]);
  EXPECT_EQ(parse_error(d).field(), "cameras[1].id");
  auto n = tiny();
  n["cameras"][0]["f_mm"] = -25;
  EXPECT_EQ(parse_error(n).field(), "cameras[0].f_mm");
}

TEST(Scenario, CameraThatSeesNoRouteIsNamed) {
  auto j = tiny();
  auto blind = j["cameras"][0];
  blind["id"] = "blind";
  blind["look_at_enu_m"] = {-30, -30, 3};  // looks west, away from the ascent
  j["cameras"].push_back(blind);
  const Error e = parse_error(j);
  EXPECT_EQ(e.field(), "cameras[1]");
  EXPECT_NE(e.reason().find("blind"), std::string::npos) << e.reason();
}

TEST(Scenario, SyntaxErrorAndMissingFile) {
  try {
    parse_scenario("{\n \"seed\": 1,\n}", "scn.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 3);
  }
  try {
    load_scenario("/nonexistent/scenario.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "/nonexistent/scenario.json");
    EXPECT_EQ(e.exit_code(), 3);
  }
}

// Found by fuzzing (docs/reliability.md "Fuzzing"): "11e308" overflows a double; the JSON
// library's out_of_range escaped instead of a rangecal::Error naming the file and line.
TEST(Scenario, NumberOutOfDoubleRangeIsAConfigError) {
  try {
    parse_scenario("{\n \"seed\": 1,\n \"start_utc\": -11e308aa\n}", "scn.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_EQ(e.file(), "scn.json");
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("scn.json:3"), std::string::npos) << e.what();
  }
}

TEST(Scenario, DemoScenarioDrawsTheRealisticPresetAndEstimatesItsModel) {
  // docs/simulator.md "A realistic preset (the demo's)"; the seed-002 reference scene stays white.
  const auto dir = rangecal::test::source_dir() / "config" / "examples";
  const Scenario demo = load_scenario((dir / "demo_scenario.json").string());
  EXPECT_EQ(demo.gnss.noise_sd_m, Eigen::Vector3d(0.003, 0.003, 0.005));
  EXPECT_EQ(demo.gnss.correlated_error.gm_sd_m, Eigen::Vector3d(0.008, 0.008, 0.014));
  EXPECT_EQ(demo.gnss.correlated_error.gm_tau_s, Eigen::Vector3d(30, 30, 30));
  EXPECT_EQ(demo.mission_error_model, "estimate");
  const Scenario white = load_scenario((dir / "seed002_scenario.json").string());
  EXPECT_EQ(white.gnss.noise_sd_m, Eigen::Vector3d(0.008, 0.008, 0.012));
  EXPECT_FALSE(white.gnss.correlated_error.active());
  EXPECT_TRUE(white.mission_error_model.is_null());
}

TEST(Scenario, DemoScenarioLoads) {
  const auto path = rangecal::test::source_dir() / "config" / "examples" / "seed002_scenario.json";
  const Scenario s = load_scenario(path.string());
  ASSERT_EQ(s.cameras.size(), 2u);
  EXPECT_EQ(s.cameras[0].camera.intr.width_px, 1280);
  EXPECT_EQ(s.cameras[0].camera.intr.height_px, 800);
  EXPECT_NEAR(s.cameras[0].camera.intr.f_mm, 135, 2);
  EXPECT_EQ(s.routes.size(), 3u);
  for (const auto& c : s.cameras)
    for (const auto& r : s.routes) {
      const double d = (c.camera.pose.center() - r.start_enu_m).head<2>().norm();
      EXPECT_GT(d, 58);  // seed 002: cameras ~64 m from the routes
      EXPECT_LT(d, 70);
    }
  int check = 0, control = 0;
  for (const auto& p : s.poles) (p.role == "check" ? check : control)++;
  EXPECT_EQ(check, 11);
  EXPECT_GE(control, 6);
}

}  // namespace
}  // namespace rangecal
