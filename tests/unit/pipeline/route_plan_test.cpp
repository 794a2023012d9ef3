// Flight planning (pipeline/analysis/route_plan.hpp, `rangecal plan`): the Cramér–Rao σ of the seed
// 002-like layout agrees with the Monte Carlo sd of the bundle on the same geometry, the principal
// point is flagged as poorly determined with the narrow lens, five ascents at mixed depths fix it
// better than three, and the CLI compares candidates side by side.
#include "pipeline/analysis/route_plan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "config/error.hpp"
#include "pipeline/analysis/monte_carlo.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

std::string demo_text() {
  return test::read_text(test::source_dir() / "config/examples/demo_scenario.json");
}

/// The demo (seed 002's three ascents, two 135 mm cameras ~64 m away) with routes replaced.
Scenario scenario_with_routes(const nlohmann::json& routes, const std::string& name) {
  nlohmann::json j = nlohmann::json::parse(demo_text());
  j["routes"] = routes;
  return parse_scenario(j.dump(), name);
}

nlohmann::json ascent(double e, double n) {
  return {{"type", "vertical"}, {"start_enu_m", {e, n, 0.8}}, {"height_m", 9.0},
          {"speed_mps", 2.5},   {"accel_mps2", 1.5},          {"hover_s", 0.5}};
}

/// Seed 002's layout: three vertical ascents ~64 m from both cameras, standing at different depths
/// (a V seen from the cameras; three ascents in one plane would leave f and depth inseparable).
nlohmann::json three_ascents() {
  return nlohmann::json::array({ascent(-5, 0.75), ascent(0, 4.75), ascent(5, 0.75)});
}

/// The same plus two ascents at other depths, one nearer and one farther along the lines of sight.
nlohmann::json five_ascents() {
  return nlohmann::json::array(
      {ascent(-5, 0.75), ascent(0, 4.75), ascent(5, 0.75), ascent(0, -3.25), ascent(0, 8.75)});
}

const ParameterBound& bound(const CameraBound& c, CameraParameter parameter) {
  for (const auto& p : c.parameters)
    if (p.parameter == parameter) return p;
  throw std::runtime_error(std::string("no parameter ") + parameter_name(parameter));
}

TEST(Plan, CramerRaoSigmaMatchesMonteCarloOfTheBundle) {
  const Scenario s = scenario_with_routes(three_ascents(), "three");
  PlanOptions o;
  o.free_sets = {{"f", "k1", "pose"}};
  const RoutePlanAnalysis a = analyse_route_plan(s, "three", o);
  ASSERT_EQ(a.free_sets.size(), 1u);

  // The same geometry calibrated for real: exact data through the true cameras as the
  // reference, then noisy trials (pixel σ and PPK σ as the plan assumes).
  std::vector<MonteCarloCamera> cams;
  for (std::size_t c = 0; c < s.cameras.size(); ++c) {
    MonteCarloCamera m;
    m.problem.camera_id = s.cameras[c].id;
    const Camera& t = s.cameras[c].camera;
    m.problem.sensor = {t.intr.width_px, t.intr.height_px, t.intr.dx_mm, t.intr.dy_mm};
    m.problem.nominal_focal_mm = 135;
    m.problem.free = {"f", "k1", "pose"};
    m.problem.pixel_sigma_px = o.pixel_sigma_px;
    m.problem.observations = planned_observations(s, c, o);
    ASSERT_EQ(static_cast<int>(m.problem.observations.size()), a.free_sets[0].cameras[c].n_points);
    m.reference = calibrate_camera("bundle", m.problem);
    cams.push_back(m);
  }
  // Check poles seen by both cameras, for the intersection comparison.
  std::vector<MonteCarloPole> poles;
  for (const ScenarioPole& p : s.poles)
    if (p.role == "check") poles.push_back({p.id, p.enu_m, {0, 1}});
  MonteCarloOptions mo;
  mo.trials = 120;
  mo.seed = 3;
  mo.pick_sigma_px = s.pick_noise_px;
  const MonteCarloResult r = run_monte_carlo(cams, poles, mo);

  for (std::size_t c = 0; c < cams.size(); ++c) {
    const CameraBound& cb = a.free_sets[0].cameras[c];
    EXPECT_FALSE(cb.singular);
    for (const ParameterStatistics& p : r.cameras[c].parameters) {
      const double crb = bound(cb, p.parameter).sigma;
      std::printf("  %s %-3s MC sd / CRB = %.3f\n", cb.camera_id.c_str(), parameter_name(p.parameter),
                  p.sd_mc / crb);
      EXPECT_NEAR(p.sd_mc / crb, 1.0, 0.25)
          << cb.camera_id << " " << parameter_name(p.parameter) << " MC " << p.sd_mc << " CRB " << crb;
    }
  }
  // Predicted intersection 1σ (√trace Σ) against the Monte Carlo RMS 3-D error at each check pole.
  for (const PoleMonteCarlo& pm : r.poles) {
    double predicted = std::numeric_limits<double>::quiet_NaN();
    for (const PoleBound& pb : a.free_sets[0].poles)
      if (pb.id == pm.id) predicted = pb.sigma_m;
    ASSERT_TRUE(std::isfinite(predicted)) << pm.id;
    EXPECT_EQ(pm.n, mo.trials) << pm.id;
    std::printf("  pole %-3s MC RMS |dR| %.4f m, plan 1σ %.4f m, ratio %.3f\n", pm.id.c_str(), pm.rms_error_m,
                predicted, pm.rms_error_m / predicted);
    EXPECT_NEAR(pm.rms_error_m / predicted, 1.0, 0.25)
        << pm.id << " MC " << pm.rms_error_m << " plan " << predicted;
  }
}

TEST(Plan, PrincipalPointPoorlyDeterminedWithNarrowLensAndImprovedByMoreRoutes) {
  const RoutePlanAnalysis three = analyse_route_plan(scenario_with_routes(three_ascents(), "3"), "3 ascents");
  const RoutePlanAnalysis five = analyse_route_plan(scenario_with_routes(five_ascents(), "5"), "5 ascents");
  ASSERT_EQ(three.free_sets.size(), 2u);  // default set, and with u0 v0
  for (std::size_t c = 0; c < 2; ++c) {
    // Default set: every parameter determined.
    for (const ParameterBound& p : three.free_sets[0].cameras[c].parameters)
      EXPECT_TRUE(std::isfinite(p.sigma)) << parameter_name(p.parameter);
    const CameraBound& b3 = three.free_sets[1].cameras[c];
    const CameraBound& b5 = five.free_sets[1].cameras[c];
    // With u0, v0 free the narrow field of view cannot separate them from the rotation.
    EXPECT_TRUE(bound(b3, CameraParameter::u0).poorly_determined)
        << bound(b3, CameraParameter::u0).max_abs_correlation;
    EXPECT_TRUE(bound(b3, CameraParameter::v0).poorly_determined)
        << bound(b3, CameraParameter::v0).max_abs_correlation;
    EXPECT_GT(bound(b3, CameraParameter::u0).sigma, 1.0);  // px: far worse than the 0.1 px centroids
    // More routes at mixed depths: more points and a clearly better principal point.
    EXPECT_GT(b5.n_points, b3.n_points);
    EXPECT_LT(bound(b5, CameraParameter::u0).sigma, 0.8 * bound(b3, CameraParameter::u0).sigma);
    EXPECT_LT(bound(b5, CameraParameter::v0).sigma, 0.8 * bound(b3, CameraParameter::v0).sigma);
  }
}

}  // namespace
}  // namespace rangecal
