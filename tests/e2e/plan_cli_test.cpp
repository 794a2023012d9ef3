// Flight planning (pipeline/analysis/route_plan.hpp, `rangecal plan`): the Cramér–Rao σ of the seed
// 002-like layout agrees with the Monte Carlo sd of the bundle on the same geometry, the principal
// point is flagged as poorly determined with the narrow lens, five ascents at mixed depths fix it
// better than three, and the CLI compares candidates side by side.
#include "pipeline/analysis/route_plan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <regex>

#include "config/error.hpp"
#include "pipeline/analysis/monte_carlo.hpp"
#include "support/ascent_routes.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

using test::five_ascents;
using test::seed002_scenario_text;
using test::three_ascents;

TEST(Plan, CliComparesCandidatesSideBySide) {
  const auto dir = test::scratch_dir("plan_cli");
  nlohmann::json j = nlohmann::json::parse(seed002_scenario_text());
  j["routes"] = three_ascents();
  test::write_text(dir / "three.json", j.dump(2));
  j["routes"] = five_ascents();
  test::write_text(dir / "five.json", j.dump(2));
  const auto r =
      test::run_cli("plan '" + (dir / "three.json").string() + "' '" + (dir / "five.json").string() +
                    "' --html '" + (dir / "plan.html").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("three"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("five"), std::string::npos);
  EXPECT_NE(r.out.find("u0 poorly determined"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("A1 check"), std::string::npos);
  const std::string html = test::read_text(dir / "plan.html");
  EXPECT_NE(html.find("<th>three</th><th>five</th>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"flag\">"), std::string::npos);  // u0 with three ascents
  EXPECT_NE(html.find("A1 check"), std::string::npos);

  // The network beside the per-camera calibration: per candidate σ per-camera, σ network and their
  // ratio, and both methods' calibration-only intersection σ through the flight volume.
  EXPECT_NE(r.out.find("per-camera calibration and network, ratio = network / per-camera"), std::string::npos)
      << r.out;
  EXPECT_TRUE(
      std::regex_search(r.out, std::regex("parameter +per-camera +network +ratio +per-camera +network")))
      << r.out;
  EXPECT_NE(r.out.find("Calibration-only intersection 1σ through the flight volume"), std::string::npos);
  for (const char* row : {"network / per-camera", "network, images 100× sharper (datum floor)",
                          "per-camera, cameras independent", "network, cross blocks dropped"})
    EXPECT_NE(r.out.find(row), std::string::npos) << row;
  EXPECT_NE(html.find("<th class=\"group\" colspan=\"3\">three</th>"), std::string::npos);
  EXPECT_NE(html.find("<th>per-camera</th><th>network</th><th>ratio</th>"), std::string::npos);
  // What surveying buys: rows 0, 2, 4 control poles, per candidate the stations free and surveyed
  // (the numbers: route_plan_test).
  EXPECT_NE(r.out.find("What surveying buys"), std::string::npos);
  for (const char* k : {"0", "2", "4"})
    EXPECT_TRUE(
        std::regex_search(r.out, std::regex(std::string("\n  ") + k +
                                            " +[0-9]+\\.[0-9]{2} +[0-9]+\\.[0-9]{2} +[0-9]+\\.[0-9]{2} "
                                            "+[0-9]+\\.[0-9]{2}\n")))
        << k << "\n"
        << r.out;
  EXPECT_NE(html.find("<th>control poles</th><th>stations free</th><th>stations 5 mm</th>"),
            std::string::npos);

  // One camera: the network is the per-camera calibration, said so; nothing to intersect.
  j["cameras"] = nlohmann::json::array({j["cameras"][0]});
  test::write_text(dir / "one.json", j.dump(2));
  const auto one =
      test::run_cli("plan '" + (dir / "one.json").string() + "' '" + (dir / "three.json").string() + "'");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_NE(one.out.find("one: one camera — the network is the per-camera calibration"), std::string::npos)
      << one.out;
  EXPECT_NE(one.out.find("= per-camera"), std::string::npos);
  EXPECT_NE(one.out.find("one: one camera — nothing to intersect"), std::string::npos);

  // The clock offset as a free parameter: its σ in seconds, and long candidate names are not cut.
  test::write_text(dir / "three_vertical_ascents.json", test::read_text(dir / "three.json"));
  const auto clock = test::run_cli("plan '" + (dir / "three_vertical_ascents.json").string() + "' '" +
                                   (dir / "five.json").string() + "' --free f,k1,pose,clock_offset");
  ASSERT_EQ(clock.exit_code, 0) << clock.err;
  EXPECT_NE(clock.out.find("clock_offset s"), std::string::npos) << clock.out;
  EXPECT_NE(clock.out.find("three_vertical_ascents"), std::string::npos) << clock.out;

  const auto missing = test::run_cli("plan '" + (dir / "nope.json").string() + "'");
  EXPECT_EQ(missing.exit_code, 3) << missing.err;
  const auto bad_free = test::run_cli("plan '" + (dir / "three.json").string() + "' --free f,zoom");
  EXPECT_EQ(bad_free.exit_code, 2) << bad_free.err;

  // A target's path: its σ per candidate, the CSV per instant; bad input named, nothing written.
  test::write_text(dir / "path.csv", "t_s,E,N,U\n0,-4,2,2\n3,0,2,6\n6,4,1,8\n");
  const auto target =
      test::run_cli("plan '" + (dir / "three.json").string() + "' --target-path '" +
                    (dir / "path.csv").string() + "' --target-csv '" + (dir / "sigma.csv").string() + "'");
  ASSERT_EQ(target.exit_code, 0) << target.err;
  EXPECT_NE(target.out.find("Target path"), std::string::npos) << target.out;
  const std::string sigma = test::read_text(dir / "sigma.csv");
  EXPECT_EQ(sigma.rfind("candidate,t_s,E,N,U,cameras,sigma_m", 0), 0u) << sigma;
  EXPECT_NE(sigma.find("three,6.000,4.0000,1.0000,8.0000,"), std::string::npos) << sigma;
  test::write_text(dir / "back.csv", "t_s,E,N,U\n0,-4,2,2\n3,0,2,6\n2,4,1,8\n");
  const auto back =
      test::run_cli("plan '" + (dir / "three.json").string() + "' --target-path '" +
                    (dir / "back.csv").string() + "' --target-csv '" + (dir / "x.csv").string() + "'");
  EXPECT_EQ(back.exit_code, 3) << back.err;
  EXPECT_NE(back.err.find("back.csv:4"), std::string::npos) << back.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.csv"));
  const auto label = test::run_cli("plan '" + (dir / "three.json").string() + "' --target-path '" +
                                   (dir / "path.csv").string() + "' --target-label-sigma 0");
  EXPECT_EQ(label.exit_code, 2) << label.err;
  EXPECT_NE(label.err.find("--target-label-sigma"), std::string::npos) << label.err;
  const auto orphan = test::run_cli("plan '" + (dir / "three.json").string() + "' --target-csv '" +
                                    (dir / "x.csv").string() + "'");
  EXPECT_EQ(orphan.exit_code, 2) << orphan.err;
}

}  // namespace
}  // namespace rangecal
