// Monte Carlo accuracy analysis (pipeline/analysis/monte_carlo.hpp, `rangecal montecarlo`): on a seed
// 002-like scene (135 mm, ~64 m, three vertical ascents) the trials' sd agrees with the bundle's
// covariance σ, the result does not depend on the thread count, and bad input fails clearly; with
// network calibrations the trials re-run the network, whose sd is the network's σ, not the
// per-camera bundle's. Under a correlated PPK error model the world noise is white + Gauss–Markov:
// its lag correlation is exp(−Δt/τ), cameras share an epoch's draw, and the trials' sd is the σ the
// bundle states under that model, far above the white model's.
#include "pipeline/analysis/monte_carlo.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "config/error.hpp"
#include "optim/network/network_input_checks.hpp"
#include "pipeline/analysis/network_plan.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/network_json.hpp"
#include "pipeline/io/stated_ppk_error_model.hpp"
#include "pipeline/simulate/scenario.hpp"
#include "support/correlated_crb.hpp"
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
      planned_network(load_scenario((test::source_dir() / "config/examples/seed002_scenario.json").string()));
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

/// Camera `c` of five 23.7 s ascents at 5 Hz (tests/support/correlated_crb.hpp: ~600 epochs over
/// 138 s, 100 mm at ~60 m) calibrated by the bundle from one correlated draw of the PPK errors, its
/// σ stated under `model`; keyed by epoch with the epochs' times, as `rangecal montecarlo` keys them.
MonteCarloCamera ascent_camera(const test::CrbNetwork& n, std::size_t c, const test::GaussMarkovPpk& ppk,
                               const PpkErrorModel& model) {
  DeterministicRandom rng(17);
  const std::vector<Eigen::Vector3d> e = test::draw_correlated_ppk_errors(n.epoch_time_s, ppk, &rng);
  const Eigen::Vector3d total = ppk.total_sigma();
  const Camera& truth = n.cameras[c].truth;
  MonteCarloCamera m;
  m.problem.camera_id = truth.id;
  m.problem.sensor = {truth.intr.width_px, truth.intr.height_px, truth.intr.dx_mm, truth.intr.dy_mm};
  m.problem.nominal_focal_mm = 100;
  m.problem.free = {"f", "k1", "pose"};
  m.problem.pixel_sigma_px = kPixelSigmaPx;
  m.problem.ppk_error = model;
  for (const test::CrbView& v : n.views) {
    if (v.camera != c || v.point >= n.epochs.size()) continue;
    BundleObservation o;
    Eigen::Vector2d uv;
    EXPECT_TRUE(project(truth, n.epochs[v.point], &uv));
    o.pixel = uv + kPixelSigmaPx * Eigen::Vector2d(rng.normal(), rng.normal());
    o.world = n.epochs[v.point] + e[v.point];
    o.world_cov = total.cwiseProduct(total).asDiagonal();
    o.time_s = n.epoch_time_s[v.point];
    m.problem.observations.push_back(o);
    m.world_noise_key.push_back(static_cast<std::int64_t>(v.point));
    m.epoch_time_s.push_back(n.epoch_time_s[v.point]);
  }
  m.reference = calibrate_camera("bundle", m.problem);
  return m;
}

TEST(MonteCarlo, CorrelatedWorldNoiseFollowsTheGaussMarkovModel) {
  const test::CrbNetwork n = test::ascent_network();
  const test::GaussMarkovPpk ppk = test::measured_ppk_model(30);
  const PpkErrorModel model = test::network_model(ppk);  // the .pos sd reports the total
  const std::vector<MonteCarloCamera> cams = {ascent_camera(n, 0, ppk, model),
                                              ascent_camera(n, 1, ppk, model)};
  MonteCarloOptions o;
  o.ppk_error = model;
  o.seed = 3;
  // Lag correlation of the drawn noise against exp(−Δt/τ), independently of the code's chain: over
  // the trials, the products e_i·e_j of camera 0's fixes Δt apart, per trial averaged over the pairs
  // and divided by σ_g² (the white part is independent between epochs). Its standard error from the
  // trials' scatter (trials are independent) sets the bar: 4 SE.
  const std::vector<double>& t = cams[0].epoch_time_s;
  std::vector<std::pair<std::size_t, std::size_t>> shared;  // observation of camera 0, of camera 1
  for (std::size_t i = 0; i < t.size(); ++i)
    for (std::size_t j = 0; j < cams[1].world_noise_key.size(); ++j)
      if (cams[0].world_noise_key[i] == cams[1].world_noise_key[j]) shared.emplace_back(i, j);
  ASSERT_GT(shared.size(), 100u);
  const int trials = 1500;
  // Within a climb (0.2 s steps) and across climbs (28.7 s apart: 23.7 s climbs, 5 s transits).
  const std::vector<double> lags = {0.2, 2.0, 10.0, 20.0, 28.7, 57.4};
  std::vector<std::vector<double>> per_trial(lags.size() * 2);  // [lag][E or U] → per-trial mean
  Eigen::Vector3d variance = Eigen::Vector3d::Zero();
  int n_variance = 0;
  for (int k = 0; k < trials; ++k) {
    const auto w = monte_carlo_world_noise(cams, o, static_cast<std::size_t>(k));
    ASSERT_EQ(w.size(), 2u);
    // An epoch both cameras saw: the same draw in both (world_noise_key).
    for (const auto& [i, j] : shared) {
      ASSERT_TRUE(w[0][i].allFinite());
      EXPECT_EQ(w[0][i], w[1][j]);
    }
    for (std::size_t i = 0; i < t.size(); ++i) variance += w[0][i].cwiseProduct(w[0][i]), ++n_variance;
    for (std::size_t l = 0; l < lags.size(); ++l) {
      double sum_e = 0, sum_u = 0;
      int pairs = 0;
      for (std::size_t i = 0; i < t.size(); ++i)
        for (std::size_t j = i + 1; j < t.size() && t[j] - t[i] < lags[l] + 0.05; ++j)
          if (std::abs(t[j] - t[i] - lags[l]) < 0.05) {
            sum_e += w[0][i].x() * w[0][j].x(), sum_u += w[0][i].z() * w[0][j].z();
            ++pairs;
          }
      ASSERT_GT(pairs, 10) << "lag " << lags[l];
      per_trial[2 * l].push_back(sum_e / pairs / (ppk.gm_h_m * ppk.gm_h_m));
      per_trial[2 * l + 1].push_back(sum_u / pairs / (ppk.gm_v_m * ppk.gm_v_m));
    }
  }
  for (std::size_t l = 0; l < lags.size(); ++l)
    for (int a = 0; a < 2; ++a) {
      const std::vector<double>& x = per_trial[2 * l + a];
      double mean = 0, ss = 0;
      for (double v : x) mean += v;
      mean /= x.size();
      for (double v : x) ss += (v - mean) * (v - mean);
      const double se = std::sqrt(ss / (x.size() - 1) / x.size());
      const double expected = std::exp(-lags[l] / 30.0);
      std::printf("  lag %4.1f s %s: correlation of the GM part %.3f ± %.3f, exp(-dt/tau) %.3f\n", lags[l],
                  a == 0 ? "E" : "U", mean, se, expected);
      EXPECT_LT(se, 0.05);  // the bar below is tight enough to tell 0.2 s from 60 s
      EXPECT_NEAR(mean, expected, 4 * se) << "lag " << lags[l];
    }
  // The total per axis is the reported sd: white scale × sd and the GM part, √(σ_w² + σ_g²).
  variance /= n_variance;
  const Eigen::Vector3d total = ppk.total_sigma();
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(std::sqrt(variance[a]) / total[a], 1.0, 0.03) << "axis " << a;
  // Drawn independently per camera (--independent-cameras), the shared epoch's noise differs.
  o.shared_world_noise = false;
  const auto w = monte_carlo_world_noise(cams, o, 0);
  EXPECT_NE(w[0][0], w[1][0]);
}

TEST(MonteCarlo, CorrelatedTrialSdIsTheCorrelatedSigma) {
  const test::CrbNetwork n = test::ascent_network();
  const test::GaussMarkovPpk ppk = test::measured_ppk_model(30);
  const PpkErrorModel model = test::network_model(ppk);  // the .pos sd reports the total
  const MonteCarloCamera correlated = ascent_camera(n, 0, ppk, model);
  MonteCarloCamera white = correlated;  // the same world, its σ stated under the white model
  white.problem.ppk_error = PpkErrorModel{};
  white.reference = calibrate_camera("bundle", white.problem);
  MonteCarloOptions o;
  o.trials = 200;
  o.seed = 11;
  o.ppk_error = model;
  const MonteCarloResult rc = run_monte_carlo({correlated}, {}, o);
  o.ppk_error = PpkErrorModel{};
  const MonteCarloResult rw = run_monte_carlo({white}, {}, o);
  // 200 trials: a Gaussian sample sd is known to 1/√(2·(n − 1)) = 5.0 % (1σ); the bar of 20 % is 4σ,
  // leaving room for the covariance's linearisation at the reference.
  for (std::size_t k = 0; k < rc.cameras[0].parameters.size(); ++k) {
    const ParameterStatistics& c = rc.cameras[0].parameters[k];
    const ParameterStatistics& w = rw.cameras[0].parameters[k];
    const std::string name = parameter_name(c.parameter);
    if (name != "f" && name != "CE" && name != "CN" && name != "CU") continue;
    std::printf("  %-2s correlated: sd MC %.4g, sigma %.4g (ratio %.3f); white: sd MC %.4g, sigma %.4g\n",
                name.c_str(), c.sd_mc, c.sd_predicted, c.sd_mc / c.sd_predicted, w.sd_mc, w.sd_predicted);
    EXPECT_NEAR(c.sd_mc / c.sd_predicted, 1.0, 0.2) << name;
    EXPECT_NEAR(w.sd_mc / w.sd_predicted, 1.0, 0.2) << name;
    // Without the GM draw the trials would scatter as the white ones, or less (the white part is
    // smaller than the reported sd): the correlated errors must show.
    EXPECT_GT(c.sd_mc, 2 * w.sd_mc) << name;
  }
}

// What `rangecal montecarlo` draws under: the model calibration.json states its σ under, read back
// from the file — the bundle's own record, the network's, none for a bundle under its own weighting.
TEST(MonteCarlo, ReadsTheModelTheCalibrationStates) {
  const test::CrbNetwork n = test::ascent_network();
  const test::GaussMarkovPpk ppk = test::measured_ppk_model(30);
  const PpkErrorModel model = test::network_model(ppk);  // the .pos sd reports the total
  MonteCarloCamera c = ascent_camera(n, 0, ppk, model);
  const std::string path = (test::scratch_dir("montecarlo_model") / "calibration.json").string();
  write_calibration_json(path, c.reference);
  const std::optional<StatedPpkErrorModel> bundle = stated_ppk_error_model(read_calibration_json(path), path);
  ASSERT_TRUE(bundle.has_value());
  EXPECT_EQ(bundle->field, "details.ppk_error_model");
  EXPECT_TRUE(same_ppk_error_model(bundle->model, model));
  EXPECT_DOUBLE_EQ(bundle->model.tau_v_s, 30.0);
  EXPECT_DOUBLE_EQ(bundle->model.gm_sd_v_m, 0.014);

  c.problem.ppk_error = PpkErrorModel{};  // the bundle's own weighting: nothing recorded
  write_calibration_json(path, calibrate_camera("bundle", c.problem));
  EXPECT_FALSE(stated_ppk_error_model(read_calibration_json(path), path).has_value());

  CalibrationResult network = c.reference;  // a network camera: the network's record
  network.details = nlohmann::json::object();
  network.details["network"] = {{"ppk_error_model", ppk_error_model_json(model, 500)}};
  const std::optional<StatedPpkErrorModel> net = stated_ppk_error_model(network, path);
  ASSERT_TRUE(net.has_value());
  EXPECT_EQ(net->field, "details.network.ppk_error_model");
  EXPECT_TRUE(same_ppk_error_model(net->model, model));
  EXPECT_FALSE(same_ppk_error_model(net->model, PpkErrorModel{}));

  network.details["ppk_error_model"] = "white";  // malformed: an error naming the field
  try {
    stated_ppk_error_model(network, path);
    ADD_FAILURE() << "a malformed model was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("details.ppk_error_model"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rangecal
