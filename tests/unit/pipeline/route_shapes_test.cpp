// Trajectories beyond vertical ascents (docs/simulator.md: "vertical ascents and any other legs"): with the
// attitude logged and the lever arm in the body frame, a mission of horizontal legs at several heights and
// depths and a diagonal climb (config/examples/plan_mixed_routes.json) calibrates through every stage to the
// demo's bars; ignoring the attitude on those legs, where the UAV leans into its accelerations, shows in the
// results; and `plan` shows what the legs add over the three vertical ascents.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "pipeline/analysis/route_plan.hpp"
#include "pipeline/demo/demo.hpp"
#include "pipeline/mission/mission_config.hpp"
#include "pipeline/simulate/scenario.hpp"
#include "pipeline/stages/mission_runner.hpp"
#include "support/paths.hpp"
#include "support/simulated_mission.hpp"

namespace rangecal {
namespace {
namespace fs = std::filesystem;

fs::path example(const char* name) {
  return test::source_dir() / "config/examples" / name;
}

// One simulation of the mixed-route mission shared by this file's tests.
const test::SimulatedRun& mixed() {
  static const test::SimulatedRun m = test::simulate_and_run_in_scratch(
      load_scenario(example("plan_mixed_routes.json").string()), "route_shapes");
  return m;
}

const DemoIntersection& bundle_intersection(const DemoResults& r) {
  for (const DemoIntersection& d : r.intersections)
    if (d.method == "bundle") return d;
  throw std::runtime_error("no bundle intersection");
}

double worst_z(const DemoResults& r) {
  double z = 0;
  for (const DemoCamera& c : r.cameras)
    for (const ParameterCheck& p : parameter_checks(c, "bundle")) z = std::max(z, std::abs(p.z()));
  return z;
}

TEST(RouteShapes, HorizontalLegsAndADiagonalClimbCalibrateWithAttitude) {
  const DemoRun& run = mixed().run;
  ASSERT_EQ(run.results.cameras.size(), 2u);
  for (const DemoCamera& c : run.results.cameras) {
    const CalibrationResult& r = c.by_method.at("bundle");
    std::printf("  %s: %d points, rms %.3f px (expected %.3f), sigma f %.3f mm\n", c.id.c_str(),
                r.reprojection.n_used, r.reprojection.rms_px, c.expected_rms_px, r.sigma(CameraParameter::f));
    EXPECT_GT(r.reprojection.n_used, 150) << c.id << ": the legs cross the field of view";
    EXPECT_LT(r.reprojection.rms_px, 1.15 * c.expected_rms_px) << c.id;
    EXPECT_GT(r.reprojection.rms_px, 0.8 * c.expected_rms_px) << c.id;
    for (const ParameterCheck& p : parameter_checks(c, "bundle"))
      EXPECT_LE(std::abs(p.z()), 3.0) << c.id << " " << p.name << " estimate " << p.estimate << " truth "
                                      << p.truth << " sigma " << p.sigma;
  }
  const DemoIntersection& b = bundle_intersection(run.results);
  std::printf("  check poles: mean dR against truth %.2f cm (max %.2f cm)\n", b.mean_dR_truth_m * 100,
              b.max_dR_truth_m * 100);
  EXPECT_EQ(b.n_check, 11);
  EXPECT_LE(b.mean_dR_truth_m, 0.010)
      << "docs/accuracy_analysis.md, Quality bars: check-pole mean ΔR ≤ 1.0 cm";
}

TEST(RouteShapes, IgnoringTheAttitudeOnTiltedLegsShowsInTheResiduals) {
  // The same files with the lever arm taken as straight down (paper eq. 5), as if no attitude had
  // been logged: on the legs the UAV leans up to ~9° into its accelerations, moving the lamp ~4 cm.
  const test::SimulatedRun& m = mixed();
  const fs::path dst = m.dir / "no_attitude";
  test::copy_mission_inputs(m.dir / "mission", dst);
  nlohmann::json j = nlohmann::json::parse(test::read_text(dst / "mission.json"));
  j["lever_arm"] = {{"vertical_m", 0.25}};
  j.erase("attitude");
  test::write_text(dst / "mission.json", j.dump(2));
  const MissionConfig cfg = load_mission_config((dst / "mission.json").string());
  run_mission(cfg);
  const DemoResults r = collect_demo_results(m.run.mission, cfg);
  double with = 0, without = 0;
  for (std::size_t c = 0; c < 2; ++c) {
    const double a = m.run.results.cameras[c].by_method.at("bundle").reprojection.rms_px;
    const double b = r.cameras[c].by_method.at("bundle").reprojection.rms_px;
    std::printf("  %s rms %.3f px with attitude, %.3f px without\n", r.cameras[c].id.c_str(), a, b);
    with += a, without += b;
  }
  std::printf("  worst |z| of f, k1, C against truth: %.2f with attitude, %.2f without\n",
              worst_z(m.run.results), worst_z(r));
  std::printf("  check poles: mean dR against truth %.2f cm with attitude, %.2f cm without\n",
              bundle_intersection(m.run.results).mean_dR_truth_m * 100,
              bundle_intersection(r).mean_dR_truth_m * 100);
  EXPECT_GT(without, 1.1 * with) << "the lamp's lean must show in the residuals";
  EXPECT_GT(worst_z(r), 3.0) << "and bias the calibration beyond its own σ";
}

TEST(RouteShapes, PlanShowsWhatTheLegsAdd) {
  PlanOptions o;
  o.free_sets = {{"f", "k1", "pose", "clock_offset", "u0", "v0"}};
  const RoutePlanAnalysis three =
      analyse_route_plan(load_scenario(example("seed002_scenario.json").string()), "3", o);
  const RoutePlanAnalysis mix =
      analyse_route_plan(load_scenario(example("plan_mixed_routes.json").string()), "mixed", o);
  auto sigma = [](const CameraBound& c, const std::string& n) {
    for (const ParameterBound& p : c.parameters)
      if (parameter_name(p.parameter) == n) return p.sigma;
    return std::numeric_limits<double>::quiet_NaN();
  };
  for (std::size_t c = 0; c < 2; ++c) {
    const CameraBound& a = three.free_sets[0].cameras[c];
    const CameraBound& b = mix.free_sets[0].cameras[c];
    ASSERT_FALSE(a.singular);
    ASSERT_FALSE(b.singular);
    for (const char* n : {"f", "u0", "v0", "clock_offset", "CU"})
      std::printf("  %s %-12s three ascents %.4g, with legs %.4g (%.2fx)\n", a.camera_id.c_str(), n,
                  sigma(a, n), sigma(b, n), sigma(a, n) / sigma(b, n));
    EXPECT_GT(b.n_points, 2 * a.n_points);
    EXPECT_LT(sigma(b, "f"), 0.5 * sigma(a, "f"));
    EXPECT_LT(sigma(b, "u0"), 0.5 * sigma(a, "u0"));
    EXPECT_LT(sigma(b, "clock_offset"), 0.7 * sigma(a, "clock_offset"));
  }
  ASSERT_EQ(three.free_sets[0].poles.size(), mix.free_sets[0].poles.size());
  for (std::size_t k = 0; k < three.free_sets[0].poles.size(); ++k)
    EXPECT_LT(mix.free_sets[0].poles[k].sigma_m, three.free_sets[0].poles[k].sigma_m)
        << three.free_sets[0].poles[k].id;
}

}  // namespace
}  // namespace rangecal
