// Monte Carlo accuracy analysis (pipeline/analysis/monte_carlo.hpp, `rangecal montecarlo`): on a seed
// 002-like scene (135 mm, ~64 m, three vertical ascents) the trials' sd agrees with the bundle's
// covariance σ, the result does not depend on the thread count, and bad input fails clearly; with
// network calibrations the trials re-run the network, whose sd is the network's σ, not the
// per-camera bundle's.
#include "pipeline/analysis/monte_carlo.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "config/error.hpp"
#include "optim/network/network_input_checks.hpp"
#include "pipeline/analysis/network_plan.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/simulate/scenario.hpp"
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

// The demo scenario's two cameras (pipeline/analysis/network_plan.hpp: noise-free epochs, control
// poles), each camera's problem keyed by network point so shared epochs share their PPK error.
struct DemoNetworkCameras {
  std::vector<MonteCarloCamera> network, bundle;
};

DemoNetworkCameras demo_network_cameras() {
  const PlannedNetwork n =
      planned_network(load_scenario((test::source_dir() / "config/examples/demo_scenario.json").string()));
  std::vector<NetworkCamera> ncs;
  DemoNetworkCameras out;
  for (std::size_t c = 0; c < n.truth.size(); ++c) {
    MonteCarloCamera m;
    m.problem.camera_id = n.truth[c].id;
    const CameraIntrinsics& in = n.truth[c].intr;
    m.problem.sensor = {in.width_px, in.height_px, in.dx_mm, in.dy_mm};
    m.problem.nominal_focal_mm = 135;
    m.problem.free = {"f", "k1", "pose"};
    m.problem.pixel_sigma_px = kPixelSigmaPx;
    m.problem.observations = camera_bundle_observations(c, n.points, n.observations);
    for (const NetworkObservation& o : n.observations)
      if (o.camera == c) m.world_noise_key.push_back(static_cast<std::int64_t>(o.point));
    out.network.push_back(m);
    NetworkCamera nc;
    nc.initial = n.truth[c];
    nc.options.free = m.problem.free;
    ncs.push_back(nc);
  }
  const NetworkResult r = network_adjust(ncs, n.points, n.observations);
  for (std::size_t c = 0; c < n.truth.size(); ++c) {
    out.bundle.push_back(out.network[c]);
    out.network[c].reference = r.cameras[c].calibration;
    out.bundle[c].reference = calibrate_camera("bundle", out.bundle[c].problem);
  }
  return out;
}

TEST(MonteCarlo, NetworkCalibrationsAreReRunAsOneNetwork) {
  const DemoNetworkCameras d = demo_network_cameras();
  MonteCarloOptions o;
  o.trials = 200;  // sd known to ±5 %
  o.seed = 5;
  const MonteCarloResult net = run_monte_carlo(d.network, {}, o);
  const MonteCarloResult per = run_monte_carlo(d.bundle, {}, o);
  for (std::size_t c = 0; c < 2; ++c) {
    ASSERT_EQ(net.cameras[c].method, "network");
    EXPECT_EQ(net.cameras[c].trials_failed, 0);
    for (std::size_t k = 0; k < net.cameras[c].parameters.size(); ++k) {
      const ParameterStatistics& a = net.cameras[c].parameters[k];
      const ParameterStatistics& b = per.cameras[c].parameters[k];
      std::printf(
          "  %s %-3s network sd MC / sigma %.3f; bundle sd MC / sigma %.3f; sd network / bundle %.3f\n",
          net.cameras[c].camera_id.c_str(), parameter_name(a.parameter), a.sd_mc / a.sd_predicted,
          b.sd_mc / b.sd_predicted, a.sd_mc / b.sd_mc);
      EXPECT_NEAR(a.sd_mc / a.sd_predicted, 1.0, 0.25) << parameter_name(a.parameter);
      EXPECT_NEAR(b.sd_mc / b.sd_predicted, 1.0, 0.25) << parameter_name(b.parameter);
    }
    // The network's f is better determined than the per-camera bundle's (docs/optimisation.md
    // "Network bundle"): the trials must show it, which they cannot if each camera is re-run alone.
    EXPECT_LT(net.cameras[c].parameters[0].sd_mc, 0.8 * per.cameras[c].parameters[0].sd_mc);
  }
}

}  // namespace
}  // namespace rangecal
