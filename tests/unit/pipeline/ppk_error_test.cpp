// The correlated PPK error (docs/simulator.md "PPK error model") against the Gauss–Markov process's
// own moments over many independent draws: stationary variance σ², autocorrelation exp(−Δt/τ) at
// irregular spacing and across a gap, τ → 0 as white noise; per-flight biases; and in the simulator:
// the .pos sd columns as the total σ, biases split at gaps, the white noise left as it was, the
// scenario keys and their errors.
#include "pipeline/simulate/ppk_error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "config/deterministic_random.hpp"
#include "config/error.hpp"
#include "pipeline/simulate/mission_simulator.hpp"
#include "support/paths.hpp"
#include "support/pos_rows.hpp"
#include "support/tiny_scenario.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Many independent series (seeds 0 … kDraws−1): the sample variance of kDraws normal values has a
// relative sd of √(2/kDraws) = 1 %, a sample correlation ρ̂ an sd of (1 − ρ²)/√kDraws ≤ 0.7 %.
// Tolerances are 4.5 of these sds.
constexpr int kDraws = 20000;
const double kVarianceTolerance = 4.5 * std::sqrt(2.0 / kDraws);

double correlation_tolerance(double rho) {
  return 4.5 * (1 - rho * rho) / std::sqrt(double(kDraws));
}

// The series of all draws: series[d][k][axis].
std::vector<std::vector<Eigen::Vector3d>> many_gauss_markov(const Eigen::Vector3d& sd,
                                                            const Eigen::Vector3d& tau,
                                                            const std::vector<double>& t) {
  std::vector<std::vector<Eigen::Vector3d>> out;
  for (int d = 0; d < kDraws; ++d) out.push_back(draw_gauss_markov(sd, tau, t, mix_seed(2024, d)));
  return out;
}

double sample_variance(const std::vector<std::vector<Eigen::Vector3d>>& s, std::size_t k, int a) {
  double m = 0, q = 0;
  for (const auto& x : s) m += x[k][a];
  m /= s.size();
  for (const auto& x : s) q += (x[k][a] - m) * (x[k][a] - m);
  return q / (s.size() - 1);
}

double sample_correlation(const std::vector<std::vector<Eigen::Vector3d>>& s, std::size_t i, std::size_t j,
                          int a) {
  double mi = 0, mj = 0;
  for (const auto& x : s) mi += x[i][a], mj += x[j][a];
  mi /= s.size();
  mj /= s.size();
  double sij = 0, sii = 0, sjj = 0;
  for (const auto& x : s) {
    sij += (x[i][a] - mi) * (x[j][a] - mj);
    sii += (x[i][a] - mi) * (x[i][a] - mi);
    sjj += (x[j][a] - mj) * (x[j][a] - mj);
  }
  return sij / std::sqrt(sii * sjj);
}

// Irregular spacing (0.05 … 1.4 s steps, one repeated time) and a last step of 500 s, ≫ every τ.
const std::vector<double> kTimes = {0.0, 0.1, 0.25, 0.3, 1.7, 1.7, 2.0, 2.05, 502.05};
const Eigen::Vector3d kSd(0.01, 0.02, 0.03);
const Eigen::Vector3d kTau(0.5, 2.0, 10.0);

TEST(PpkError, GaussMarkovIsStationaryWithVarianceSigmaSquared) {
  const auto s = many_gauss_markov(kSd, kTau, kTimes);
  double worst = 0;
  for (std::size_t k = 0; k < kTimes.size(); ++k)
    for (int a = 0; a < 3; ++a) {
      const double ratio = sample_variance(s, k, a) / (kSd[a] * kSd[a]);
      EXPECT_NEAR(ratio, 1.0, kVarianceTolerance) << "epoch " << k << " axis " << a;
      worst = std::max(worst, std::abs(ratio - 1));
    }
  std::cout << "GM variance / σ²: largest |ratio − 1| " << worst << " (tolerance " << kVarianceTolerance
            << ")\n";
}

TEST(PpkError, AutocorrelationIsExpMinusDtOverTauAtIrregularSpacing) {
  const auto s = many_gauss_markov(kSd, kTau, kTimes);
  double worst = 0;
  // Every pair of epochs, not only neighbours: lag-k correlation = the product of the steps' φ.
  for (std::size_t i = 0; i < kTimes.size(); ++i)
    for (std::size_t j = i + 1; j < kTimes.size(); ++j)
      for (int a = 0; a < 3; ++a) {
        const double rho = std::exp(-(kTimes[j] - kTimes[i]) / kTau[a]);
        const double r = sample_correlation(s, i, j, a);
        if (rho > 0.999999) {
          EXPECT_NEAR(r, 1.0, 1e-12) << i << "," << j;  // the repeated time: the same value
          continue;
        }
        EXPECT_NEAR(r, rho, correlation_tolerance(rho)) << "epochs " << i << "," << j << " axis " << a;
        worst = std::max(worst, std::abs(r - rho) / correlation_tolerance(rho) * 4.5);
      }
  std::cout << "GM autocorrelation: largest |r − exp(−Δt/τ)| = " << worst << " sds of r\n";
}

TEST(PpkError, GapMuchLongerThanTauDecorrelates) {
  const auto s = many_gauss_markov(kSd, kTau, kTimes);
  const std::size_t last = kTimes.size() - 1;  // 500 s after the one before: exp(−50) at τ = 10 s
  for (int a = 0; a < 3; ++a) {
    const double r = sample_correlation(s, last - 1, last, a);
    EXPECT_LT(std::abs(r), correlation_tolerance(0)) << a;
    EXPECT_NEAR(sample_variance(s, last, a) / (kSd[a] * kSd[a]), 1.0, kVarianceTolerance);
  }
  // Across a gap of 1.5 τ the correlation is still exp(−1.5), not reset.
  const auto g = many_gauss_markov(kSd, kTau, {0.0, 15.0});
  EXPECT_NEAR(sample_correlation(g, 0, 1, 2), std::exp(-1.5), correlation_tolerance(std::exp(-1.5)));
}

TEST(PpkError, TauToZeroIsWhiteNoise) {
  std::vector<double> t;
  for (int k = 0; k < 6; ++k) t.push_back(0.1 * k);
  const auto s = many_gauss_markov(kSd, Eigen::Vector3d::Constant(1e-6), t);
  for (std::size_t k = 0; k + 1 < t.size(); ++k)
    for (int a = 0; a < 3; ++a) {
      EXPECT_LT(std::abs(sample_correlation(s, k, k + 1, a)), correlation_tolerance(0)) << k << "," << a;
      EXPECT_NEAR(sample_variance(s, k + 1, a) / (kSd[a] * kSd[a]), 1.0, kVarianceTolerance);
    }
}

TEST(PpkError, ZeroSigmaAxisIsExactlyZero) {
  const auto g = draw_gauss_markov(Eigen::Vector3d(0, 0.01, 0), kTau, kTimes, 5);
  for (const auto& x : g) {
    EXPECT_EQ(x[0], 0.0);
    EXPECT_EQ(x[2], 0.0);
  }
  EXPECT_TRUE(
      draw_ppk_correlated_error(PpkCorrelatedError{}, kTimes, std::vector<int>(kTimes.size(), 0), 1, 2) ==
      std::vector<Eigen::Vector3d>(kTimes.size(), Eigen::Vector3d::Zero()));
}

TEST(PpkError, FlightBiasConstantWithinAFlightWithSigmaBetweenFlights) {
  const std::vector<int> flight = {0, 0, 0, 1, 1, 2, 2, 2, 0};  // flight 0 again at the end
  const Eigen::Vector3d sd(0.004, 0.006, 0.02);
  std::vector<std::vector<Eigen::Vector3d>> s;
  for (int d = 0; d < kDraws; ++d) s.push_back(draw_flight_bias(sd, flight, mix_seed(77, d)));
  for (const auto& b : s) {
    for (std::size_t k = 1; k < flight.size(); ++k)
      if (flight[k] == flight[k - 1]) {
        ASSERT_EQ(b[k], b[k - 1]);
      }
    ASSERT_EQ(b[8], b[0]);  // a flight's bias is its own, not the order's
    ASSERT_NE(b[2], b[3]);
  }
  // Epochs 0, 3, 5 are flights 0, 1, 2: each N(0, σ_b²), independent of each other.
  for (std::size_t k : {0u, 3u, 5u})
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(sample_variance(s, k, a) / (sd[a] * sd[a]), 1.0, kVarianceTolerance) << k << "," << a;
  for (int a = 0; a < 3; ++a) {
    EXPECT_LT(std::abs(sample_correlation(s, 0, 3, a)), correlation_tolerance(0));
    EXPECT_LT(std::abs(sample_correlation(s, 3, 5, a)), correlation_tolerance(0));
  }
}

TEST(PpkError, CombinedErrorAddsGaussMarkovAndBias) {
  PpkCorrelatedError m;
  m.gm_sd_m = Eigen::Vector3d(0.003, 0.003, 0.012);
  m.gm_tau_s = Eigen::Vector3d::Constant(1.0);
  m.flight_bias_sd_m = Eigen::Vector3d(0.004, 0.004, 0.005);
  const std::vector<double> t = {0, 0.1, 0.2, 5.0, 5.1};
  const std::vector<int> f = {0, 0, 0, 1, 1};
  const auto e = draw_ppk_correlated_error(m, t, f, 11, 12);
  const auto g = draw_gauss_markov(m.gm_sd_m, m.gm_tau_s, t, 11);
  const auto b = draw_flight_bias(m.flight_bias_sd_m, f, 12);
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_EQ(e[k], g[k] + b[k]);
  // The reported sd: √(white² + σ_GM²), a 3-4-5 and a 5-12-13 triangle.
  const Eigen::Vector3d sd = reported_sd_m(Eigen::Vector3d(0.004, 0.004, 0.005), m);
  EXPECT_NEAR(sd[0], 0.005, 1e-15);
  EXPECT_NEAR(sd[2], 0.013, 1e-15);
}

// --- in the simulator -------------------------------------------------------------------------

Scenario scenario_of(const json& j) {
  return parse_scenario(j.dump(), "tiny.json");
}

TEST(PpkErrorSimulation, PosSdColumnsAreTheTotalSigma) {
  json j = test::tiny_scenario();
  j["gnss"]["noise_sd_m"] = {0.003, 0.003, 0.005};
  j["gnss"]["gauss_markov"] = {{"sd_m", {{"horizontal", 0.004}, {"vertical", 0.012}}},
                               {"tau_s", {{"horizontal", 30}, {"vertical", 20}}}};
  j["gnss"]["float_intervals"] = {{2.0, 2.25}};
  j["gnss"]["float_noise_factor"] = 10;
  const fs::path dir = test::scratch_dir("ppk_error_sd");
  write_mission(simulate_mission(scenario_of(j)), dir.string());
  int floats = 0;
  for (const auto& r : test::pos_rows(dir / "gnss" / "rover.pos")) {
    const bool is_float = r[5] == "2";
    // fix: √(0.3² + 0.4²) = 0.5 cm, √(0.5² + 1.2²) = 1.3 cm; float: the white part × 10 only:
    // √(3² + 0.4²) = 3.0265 cm, √(5² + 1.2²) = 5.142 cm.
    EXPECT_EQ(r[7], is_float ? "0.0303" : "0.0050") << r[1];  // sdn
    EXPECT_EQ(r[8], is_float ? "0.0303" : "0.0050") << r[1];  // sde
    EXPECT_EQ(r[9], is_float ? "0.0514" : "0.0130") << r[1];  // sdu
    floats += is_float;
  }
  EXPECT_EQ(floats, 3);
  const json truth = json::parse(test::read_text(dir / "truth.json"));
  EXPECT_EQ(truth["noise"]["gnss_gauss_markov"]["sd_enu_m"], json({0.004, 0.004, 0.012}));
  EXPECT_EQ(truth["noise"]["gnss_gauss_markov"]["tau_enu_s"], json({30.0, 30.0, 20.0}));
  EXPECT_FALSE(truth["noise"].contains("gnss_flight_bias_sd_enu_m"));
  EXPECT_NEAR(truth["epochs"][0]["sd_enu_m"][2].get<double>(), 0.013, 1e-15);
}

TEST(PpkErrorSimulation, MissionStatesTheModelItDrew) {
  // The mission.json of a correlated scenario gives the network the drawn model (docs/gnss.md "PPK
  // error model"): white 0.3 / 0.5 cm of a reported 0.5 / 1.3 cm → scales 0.6 and 5/13; GM as drawn.
  json j = test::tiny_scenario();
  j["gnss"]["noise_sd_m"] = {0.003, 0.003, 0.005};
  j["gnss"]["gauss_markov"] = {{"sd_m", {{"horizontal", 0.004}, {"vertical", 0.012}}},
                               {"tau_s", {{"horizontal", 30}, {"vertical", 20}}}};
  const fs::path dir = test::scratch_dir("ppk_error_model");
  write_mission(simulate_mission(scenario_of(j)), dir.string());
  const json m = json::parse(test::read_text(dir / "mission.json"))["gnss"]["error_model"];
  EXPECT_NEAR(m["white_scale"]["horizontal"].get<double>(), 0.6, 1e-12);
  EXPECT_NEAR(m["white_scale"]["vertical"].get<double>(), 5.0 / 13, 1e-12);
  EXPECT_EQ(m["gauss_markov"]["sd_m"]["horizontal"].get<double>(), 0.004);
  EXPECT_EQ(m["gauss_markov"]["sd_m"]["vertical"].get<double>(), 0.012);
  EXPECT_EQ(m["gauss_markov"]["tau_s"]["horizontal"].get<double>(), 30);
  EXPECT_EQ(m["gauss_markov"]["tau_s"]["vertical"].get<double>(), 20);
  // A white scenario's mission has none: the network stays white.
  const fs::path white = test::scratch_dir("ppk_error_model_white");
  write_mission(simulate_mission(scenario_of(test::tiny_scenario())), white.string());
  EXPECT_FALSE(json::parse(test::read_text(white / "mission.json"))["gnss"].contains("error_model"));
}

TEST(PpkErrorSimulation, CorrelatedErrorAddsToTheUnchangedWhiteNoise) {
  json white = test::tiny_scenario();
  white["gnss"]["gaps"] = {{1.0, 1.45}};
  json corr = white;
  corr["gnss"]["gauss_markov"] = {{"sd_m", {0.004, 0.005, 0.012}}, {"tau_s", {30, 30, 20}}};
  corr["gnss"]["flight_bias_sd_m"] = {{"horizontal", 0.02}, {"vertical", 0.03}};
  const SimMission a = simulate_mission(scenario_of(white));
  const SimMission b = simulate_mission(scenario_of(corr));
  ASSERT_EQ(a.epochs.size(), b.epochs.size());
  // The difference is the correlated part alone (same white draws), from the documented streams:
  // GM mix_seed(seed, 8) over the written epochs, flight f's bias mix_seed(mix_seed(seed, 9), f); the
  // gap 1.0 … 1.45 s starts flight 1.
  std::vector<double> t;
  std::vector<int> f;
  for (const SimEpoch& e : b.epochs) {
    t.push_back(e.t_s);
    f.push_back(e.t_s > 1.45 ? 1 : 0);
  }
  const auto g = draw_gauss_markov(Eigen::Vector3d(0.004, 0.005, 0.012), Eigen::Vector3d(30, 30, 20), t,
                                   mix_seed(11, 8));
  const auto bias = draw_flight_bias(Eigen::Vector3d(0.02, 0.02, 0.03), f, mix_seed(11, 9));
  EXPECT_NE(bias.front(), bias.back());
  for (std::size_t k = 0; k < t.size(); ++k) {
    EXPECT_EQ(a.epochs[k].antenna_true, b.epochs[k].antenna_true);
    EXPECT_LT((b.epochs[k].antenna_measured - a.epochs[k].antenna_measured - g[k] - bias[k]).norm(), 1e-12)
        << t[k];
  }
  // A gap that removes no epoch (between two 10 Hz epochs) still starts a new flight: lock was lost.
  json thin = corr;
  thin["gnss"]["gaps"] = {{2.01, 2.02}};
  thin["gnss"].erase("gauss_markov");
  const SimMission c = simulate_mission(scenario_of(thin));
  const SimMission d = simulate_mission(scenario_of(test::tiny_scenario()));
  ASSERT_EQ(c.epochs.size(), d.epochs.size());
  const auto offset = [&](std::size_t k) {
    return c.epochs[k].antenna_measured - d.epochs[k].antenna_measured;
  };
  for (std::size_t k = 1; k < c.epochs.size(); ++k) {
    if (std::abs(c.epochs[k].t_s - 2.1) < 1e-9)
      EXPECT_GT((offset(k) - offset(k - 1)).norm(), 1e-4);
    else
      EXPECT_LT((offset(k) - offset(k - 1)).norm(), 1e-12) << c.epochs[k].t_s;
  }
}

TEST(PpkErrorSimulation, ZeroCorrelatedErrorKeepsTheBytes) {
  json j = test::tiny_scenario();
  j["gnss"]["gaps"] = {{1.0, 1.45}};
  json z = j;
  z["gnss"]["gauss_markov"] = {{"sd_m", {0, 0, 0}}, {"tau_s", {30, 30, 30}}};
  z["gnss"]["flight_bias_sd_m"] = {0, 0, 0};
  const SimMission a = simulate_mission(scenario_of(j));
  const SimMission b = simulate_mission(scenario_of(z));
  EXPECT_EQ(format_truth_json(a), format_truth_json(b));
}

TEST(PpkErrorSimulation, ScenarioKeysAndErrors) {
  json j = test::tiny_scenario();
  j["gnss"]["gauss_markov"] = {{"sd_m", {0.001, 0.002, 0.003}},
                               {"tau_s", {{"horizontal", 40}, {"vertical", 90}}}};
  j["gnss"]["flight_bias_sd_m"] = {{"horizontal", 0.01}, {"vertical", 0.02}};
  const PpkCorrelatedError c = scenario_of(j).gnss.correlated_error;
  EXPECT_EQ(c.gm_sd_m, Eigen::Vector3d(0.001, 0.002, 0.003));
  EXPECT_EQ(c.gm_tau_s, Eigen::Vector3d(40, 40, 90));
  EXPECT_EQ(c.flight_bias_sd_m, Eigen::Vector3d(0.01, 0.01, 0.02));
  EXPECT_FALSE(scenario_of(test::tiny_scenario()).gnss.correlated_error.active());

  const auto field_of = [](const json& bad) {
    try {
      parse_scenario(bad.dump(), "scn.json");
    } catch (const Error& e) {
      EXPECT_EQ(e.exit_code(), 2);
      EXPECT_EQ(e.file(), "scn.json");
      return e.field();
    }
    ADD_FAILURE() << "no error for " << bad["gnss"].dump();
    return std::string();
  };
  json t0 = j;
  t0["gnss"]["gauss_markov"]["tau_s"] = {30, 0, 30};  // τ must be > 0
  EXPECT_EQ(field_of(t0), "gnss.gauss_markov.tau_s");
  json nt = j;
  nt["gnss"]["gauss_markov"].erase("tau_s");
  EXPECT_EQ(field_of(nt), "gnss.gauss_markov.tau_s");
  json ns = j;
  ns["gnss"]["gauss_markov"]["sd_m"] = {{"horizontal", -0.001}, {"vertical", 0.01}};
  EXPECT_EQ(field_of(ns), "gnss.gauss_markov.sd_m");
  json nv = j;
  nv["gnss"]["gauss_markov"]["sd_m"] = {{"horizontal", 0.001}};
  EXPECT_EQ(field_of(nv), "gnss.gauss_markov.sd_m.vertical");
  json uk = j;
  uk["gnss"]["gauss_markov"]["tau"] = 3;
  EXPECT_EQ(field_of(uk), "gnss.gauss_markov.tau");
  json nb = j;
  nb["gnss"]["flight_bias_sd_m"] = {0.01, 0.01};
  EXPECT_EQ(field_of(nb), "gnss.flight_bias_sd_m");
}

}  // namespace
}  // namespace rangecal
