// Monte Carlo accuracy analysis (pipeline/analysis/monte_carlo.hpp, `rangecal montecarlo`): on a seed
// 002-like scene (135 mm, ~64 m, three vertical ascents) the trials' sd agrees with the bundle's
// covariance σ, the result does not depend on the thread count, and bad input fails clearly.
#include "pipeline/analysis/monte_carlo.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "config/error.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "support/paths.hpp"
#include "support/single_camera_mission.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

constexpr double kWorldSigmaM = 0.01;  // PPK-like 1 cm per axis
constexpr double kPixelSigmaPx = 0.1;

/// The seed 002-like scene: three ascents (40 points each) and four pole tops, observed with
/// 1 cm world noise and 0.1 px pixel noise (the data a mission would have calibrated from).
CalibrationProblem range_problem(const Camera& truth, std::uint64_t seed) {
  const auto pts = test::observe(truth, test::range_world_points(truth), kPixelSigmaPx, kWorldSigmaM, seed);
  CalibrationProblem p;
  p.camera_id = "cam1";
  p.sensor = {truth.intr.width_px, truth.intr.height_px, truth.intr.dx_mm, truth.intr.dy_mm};
  p.nominal_focal_mm = 135;
  p.free = {"f", "k1", "pose"};
  p.pixel_sigma_px = kPixelSigmaPx;
  for (const auto& c : pts) {
    BundleObservation o;
    o.world = c.world;
    o.pixel = c.pixel;
    o.world_cov = Eigen::Matrix3d::Identity() * kWorldSigmaM * kWorldSigmaM;
    p.observations.push_back(o);
  }
  return p;
}

TEST(MonteCarlo, TrialSdAgreesWithCovarianceSigma) {
  const Camera truth = test::range_camera(-3.4e-4);
  MonteCarloCamera c;
  c.problem = range_problem(truth, 11);
  c.reference = calibrate_camera("bundle", c.problem);
  MonteCarloOptions o;
  o.trials = 150;
  o.seed = 7;
  const MonteCarloResult r = run_monte_carlo({c}, {}, o);
  ASSERT_EQ(r.cameras.size(), 1u);
  const CameraMonteCarlo& m = r.cameras[0];
  EXPECT_EQ(m.trials_ok, 150);
  ASSERT_EQ(m.parameters.size(), 8u);  // f k1 wx wy wz CE CN CU
  for (const ParameterStatistics& p : m.parameters) {
    ASSERT_TRUE(std::isfinite(p.sd_predicted) && p.sd_predicted > 0) << parameter_name(p.parameter);
    std::printf("  %-3s sd MC / sd predicted = %.3f, bias / sd MC = %+.3f\n", parameter_name(p.parameter),
                p.sd_mc / p.sd_predicted, p.bias_mc / p.sd_mc);
    // 150 trials: the sd is known to ±6 % (1/√(2n)); the bar is 25 %.
    EXPECT_NEAR(p.sd_mc / p.sd_predicted, 1.0, 0.25)
        << parameter_name(p.parameter) << " sd MC " << p.sd_mc << " predicted " << p.sd_predicted;
    // The estimator is nearly unbiased at this noise: the bias is well inside one sd.
    EXPECT_LT(std::abs(p.bias_mc), 0.5 * p.sd_mc) << parameter_name(p.parameter);
  }
  // The reference values are the reference calibration's (the simulated truth), not the trials'.
  EXPECT_DOUBLE_EQ(m.parameters[0].estimate, c.reference.camera.intr.f_mm);
}

TEST(MonteCarlo, ZeroNoiseReproducesTheReference) {
  // Without noise every trial re-calibrates exact data: sd ≈ 0 and bias ≈ 0 (an independent check
  // that the trials really re-run the calibration on regenerated pixels).
  const Camera truth = test::range_camera(-3.4e-4);
  MonteCarloCamera c;
  c.problem = range_problem(truth, 3);
  c.reference = calibrate_camera("bundle", c.problem);
  MonteCarloOptions o;
  o.trials = 4;
  o.world_noise = o.image_noise = false;
  const MonteCarloResult r = run_monte_carlo({c}, {}, o);
  for (const ParameterStatistics& p : r.cameras[0].parameters) {
    EXPECT_LT(std::abs(p.bias_mc), 1e-3 * p.sd_predicted) << parameter_name(p.parameter);
    EXPECT_LT(p.sd_mc, 1e-3 * p.sd_predicted) << parameter_name(p.parameter);
  }
}

TEST(MonteCarlo, IdenticalForAnyThreadCount) {
  const Camera truth = test::range_camera(-3.4e-4);
  MonteCarloCamera c;
  c.problem = range_problem(truth, 5);
  c.reference = calibrate_camera("bundle", c.problem);
  MonteCarloOptions o;
  o.trials = 24;
  o.threads = 1;
  const std::string one = format_montecarlo_csv(run_monte_carlo({c}, {}, o));
  o.threads = 2;
  const std::string two = format_montecarlo_csv(run_monte_carlo({c}, {}, o));
  EXPECT_EQ(one, two);
  EXPECT_EQ(one.substr(0, one.find('\n')), "camera,parameter,estimate,bias_mc,sd_mc,sd_predicted");
  o.seed = 99;  // and the seed matters
  EXPECT_NE(format_montecarlo_csv(run_monte_carlo({c}, {}, o)), one);
}

TEST(MonteCarlo, RejectsZeroTrials) {
  const Camera truth = test::range_camera();
  MonteCarloCamera c;
  c.problem = range_problem(truth, 5);
  c.reference = calibrate_camera("bundle", c.problem);
  MonteCarloOptions o;
  o.trials = 0;
  try {
    run_monte_carlo({c}, {}, o);
    ADD_FAILURE() << "0 trials accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 2);
  }
}

// Two cameras that saw the same GNSS epochs share their errors (world_noise_key). In the limit of
// one common error for every point of both cameras, each camera moves rigidly with the world, so
// every check pole is found displaced by exactly that error: all poles show the same RMS. Drawn
// independently per camera, the poles' errors differ.
TEST(MonteCarlo, SharedEpochNoiseMovesBothCamerasTogether) {
  const Camera a = test::range_camera_at("cam1", {-30, 0, 1.5}, {0.5, 64, 6}, -3.4e-4);
  const Camera b = test::range_camera_at("cam2", {30, 0, 1.5}, {0.5, 64, 6}, -3.4e-4);
  std::vector<MonteCarloCamera> cams;
  for (const Camera& truth : {a, b}) {
    MonteCarloCamera c;
    c.problem = range_problem(truth, 3);
    for (auto& o : c.problem.observations) o.world_cov = Eigen::Matrix3d::Identity() * 1e-4;
    c.reference = calibrate_camera("bundle", c.problem);
    c.world_noise_key.assign(c.problem.observations.size(), 0);  // one error for every point
    cams.push_back(c);
  }
  const std::vector<MonteCarloPole> poles = {{"P1", {-1.0, 63.0, 4.0}, {0, 1}},
                                             {"P2", {2.0, 65.0, 7.0}, {0, 1}}};
  MonteCarloOptions o;
  o.trials = 60;
  o.image_noise = false;
  o.pick_sigma_px = 1e-4;
  const MonteCarloResult shared = run_monte_carlo(cams, poles, o);
  ASSERT_EQ(shared.poles.size(), 2u);
  std::printf("  shared: RMS %.5f / %.5f m\n", shared.poles[0].rms_error_m, shared.poles[1].rms_error_m);
  EXPECT_NEAR(shared.poles[0].rms_error_m, shared.poles[1].rms_error_m, 1e-5);
  EXPECT_NEAR(shared.poles[0].rms_error_m, 0.01 * std::sqrt(3.0), 0.004);  // |bias| of a 1 cm per axis draw
  o.shared_world_noise = false;
  const MonteCarloResult independent = run_monte_carlo(cams, poles, o);
  std::printf("  independent: RMS %.5f / %.5f m\n", independent.poles[0].rms_error_m,
              independent.poles[1].rms_error_m);
  EXPECT_GT(std::abs(independent.poles[0].rms_error_m - independent.poles[1].rms_error_m), 1e-4);
  cams[0].world_noise_key.pop_back();
  EXPECT_THROW(run_monte_carlo(cams, poles, o), Error);  // one key per observation
}

}  // namespace
}  // namespace rangecal
