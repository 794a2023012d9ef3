// The independent bound for time-correlated PPK errors (tests/support/correlated_crb.hpp;
// docs/accuracy_analysis.md "Correlated PPK errors: the independent bound"):
//   - the drawn errors (exact AR(1) recursion) have the modelled covariance Σ_PPK;
//   - (that it equals the network's own a-priori covariance, white and correlated, is
//     tests/unit/optim/network_gauss_markov_test.cpp);
//   - the measured mission's setting (two 100 mm cameras 45–80 m from five ascents, ~590 fixed
//     epochs over ~140 s; white 0.3/0.5 cm + GM 0.8/1.4 cm, τ = 30 s): the calibration-only
//     flight-volume intersection σ of the bound with 0 and 2 control poles and with the stations
//     surveyed, of a white-noise network as it believes, and as it really is (sandwich);
//   - a Monte Carlo of the white-noise network on correlated errors matches the sandwich (its
//     whitened errors in the linear regime, its intersection error at the measured size).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "support/correlated_crb.hpp"

namespace rangecal::test {
namespace {

using Eigen::MatrixXd;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::VectorXd;

TEST(CorrelatedCrb, DrawnErrorsHaveTheModelledCovariance) {
  // 20 epochs at 5 Hz, a 12 s gap, 20 more: lags within and across the gap. τ = 5 s so that the
  // correlation falls from 0.96 to 0.04 over the series.
  std::vector<double> t;
  for (int k = 0; k < 40; ++k) t.push_back(0.2 * k + (k >= 20 ? 12.0 : 0.0));
  GaussMarkovPpk m = measured_ppk_model();
  m.tau_h_s = 5, m.tau_v_s = 5;
  const PpkJointCovariance model = ppk_joint_covariance(t, m);
  constexpr int kDraws = 10000;
  DeterministicRandom rng(11);
  const Eigen::Index n = 3 * static_cast<Eigen::Index>(t.size());
  MatrixXd S = MatrixXd::Zero(n, n);
  for (int d = 0; d < kDraws; ++d) {
    const std::vector<Vector3d> e = draw_correlated_ppk_errors(t, m, &rng);
    VectorXd v(n);
    for (std::size_t k = 0; k < t.size(); ++k) v.segment<3>(3 * static_cast<Eigen::Index>(k)) = e[k];
    S.noalias() += v * v.transpose();
  }
  S /= kDraws;
  // Each sample covariance has sd √((C_ii·C_jj + C_ij²)/D): every one of the 7,260 distinct entries
  // within 5.5 of those sd (a Gaussian exceeds 5.5 sd with probability 4e-8).
  double worst = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) {
      const MatrixXd& C = model.cov;
      const double sd = std::sqrt((C(i, i) * C(j, j) + C(i, j) * C(i, j)) / kDraws);
      worst = std::max(worst, std::abs(S(i, j) - C(i, j)) / sd);
    }
  std::printf("drawn PPK errors: largest |sample − model| covariance = %.2f sd\n", worst);
  EXPECT_LT(worst, 5.5);
  // The model itself: lag 0.2 s within a climb, and 12.2 s across the gap, vertical.
  EXPECT_NEAR(model.cov(2, 2), 0.005 * 0.005 + 0.014 * 0.014, 1e-15);
  EXPECT_NEAR(model.cov(3 * 19 + 2, 3 * 20 + 2), 0.014 * 0.014 * std::exp(-12.2 / 5), 1e-15);
  EXPECT_EQ(model.cov(0, 1), 0.0);  // no correlation between axes
  EXPECT_LT((model.cov * model.information - MatrixXd::Identity(n, n)).cwiseAbs().maxCoeff(), 1e-9);
}

struct SettingFigures {
  double bound = 0, white_believed = 0, sandwich = 0;
};

TEST(CorrelatedCrb, MeasuredMissionSetting) {
  const auto t0 = std::chrono::steady_clock::now();
  const GaussMarkovPpk model = measured_ppk_model();
  const CrbNetwork lamp_only = ascent_network();
  const PpkJointCovariance truth = ppk_joint_covariance(lamp_only.epoch_time_s, model);
  const PpkJointCovariance white = ppk_joint_covariance(lamp_only.epoch_time_s, model.as_white());
  const std::vector<Vector3d> volume = flight_volume(lamp_only, 400, 77);
  std::printf("measured-mission setting: %zu epochs over %.1f s, %zu views, %zu volume points\n",
              lamp_only.epochs.size(), lamp_only.epoch_time_s.back() - lamp_only.epoch_time_s.front(),
              lamp_only.views.size(), volume.size());
  ASSERT_GE(lamp_only.epochs.size(), 500u);
  ASSERT_GE(volume.size(), 300u);
  const char* names[3] = {"no poles", "2 control poles", "2 poles + stations 5 mm"};
  SettingFigures f[3];
  for (int i = 0; i < 3; ++i) {
    AscentNetworkOptions o;
    o.control_poles = i == 0 ? 0 : 2;
    o.station_sigma_m = i == 2 ? 0.005 : 0;
    const CrbNetwork n = ascent_network(o);
    ASSERT_EQ(n.epochs.size(), lamp_only.epochs.size());
    const CameraJointCovariance bound = cramer_rao_bound(n, truth);
    const CameraJointCovariance believed = cramer_rao_bound(n, white);
    const CameraJointCovariance actual = sandwich_covariance(n, white, truth);
    f[i] = {intersection_sigma_m(n, bound, volume), intersection_sigma_m(n, believed, volume),
            intersection_sigma_m(n, actual, volume)};
    std::printf("%-24s bound %.3f cm | white network believes %.3f cm, actual (sandwich) %.3f cm (x%.1f)\n",
                names[i], 100 * f[i].bound, 100 * f[i].white_believed, 100 * f[i].sandwich,
                f[i].sandwich / f[i].white_believed);
    for (std::size_t c = 0; c < n.cameras.size(); ++c) {
      const VectorXd sb = bound.sigma(c), sw = believed.sigma(c), sa = actual.sigma(c);
      std::printf(
          "    %s σ f %.4f / %.4f / %.4f mm, σ CU %.2f / %.2f / %.2f cm (bound / believed / actual)\n",
          n.cameras[c].truth.id.c_str(), sb[0], sw[0], sa[0], 100 * sb[7], 100 * sw[7], 100 * sa[7]);
    }
    // Robust relations: the bound is no lower than what the white network believes (its errors are
    // correlated, so it has less information than it counts), and the white network's actual error
    // is no lower than the bound (Cramér–Rao) and well above what it believes.
    EXPECT_GE(f[i].bound, f[i].white_believed) << names[i];
    EXPECT_GE(f[i].sandwich, f[i].bound * (1 - 1e-9)) << names[i];
    EXPECT_GT(f[i].sandwich / f[i].white_believed, 3.0) << names[i];
  }
  // More control lowers the bound: poles, then surveyed stations.
  EXPECT_GT(f[0].bound, f[1].bound);
  EXPECT_GT(f[1].bound, f[2].bound);
  std::printf(
      "(the measured mission: bound 1.15 / 0.74 / 0.61 cm; the white network predicted ~0.15 cm, "
      "actual 0.6-1.2 cm)\n");
  std::printf("setting test took %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

/// What a Monte Carlo of the white-noise network gives on a small network (three climbs at 2 Hz, ~140
/// epochs over ~75 s, two control poles): correlated PPK errors of `model`, pixel and survey noise
/// drawn here; network_adjust with white PPK weights and plain least squares (no robust loss, no
/// outlier rejection), the estimator whose linearised covariance is the sandwich.
struct MonteCarloFigures {
  double d2_actual = 0;    ///< mean Mahalanobis d² of the camera errors under the sandwich
  double d2_believed = 0;  ///< the same under the white network's own covariance
  int parameters = 0;      ///< d²'s degrees of freedom
  double e2_mean = 0;      ///< mean over the draws of the volume's mean squared intersection error (m²)
  double e2_sd = 0;        ///< its sampling sd (m²)
  double sandwich_m = 0;   ///< the sandwich's intersection σ
  double believed_m = 0;   ///< the white network's own
};

MonteCarloFigures white_network_monte_carlo(const GaussMarkovPpk& model, int draws, std::uint64_t seed) {
  AscentNetworkOptions o;
  o.ascents = 3, o.rate_hz = 2, o.control_poles = 2;
  const CrbNetwork n = ascent_network(o);
  const PpkJointCovariance truth = ppk_joint_covariance(n.epoch_time_s, model);
  const PpkJointCovariance white = ppk_joint_covariance(n.epoch_time_s, model.as_white());
  const CameraJointCovariance actual = sandwich_covariance(n, white, truth);
  const CameraJointCovariance believed = cramer_rao_bound(n, white);
  const std::vector<Vector3d> volume = flight_volume(n, 200, 78);
  NetworkOptions opt = plain_least_squares_network();
  const Eigen::Index P = actual.joint.rows();
  const Eigen::LLT<MatrixXd> la(actual.joint), lb(believed.joint);
  DeterministicRandom rng(seed);
  MonteCarloFigures f;
  f.parameters = static_cast<int>(P);
  std::vector<double> e2;  // per draw: mean over the volume of the squared intersection error
  for (int d = 0; d < draws; ++d) {
    NetworkNoise noise;
    noise.ppk_error = draw_correlated_ppk_errors(n.epoch_time_s, model, &rng);
    for (std::size_t j = 0; j < n.poles.size(); ++j)
      noise.pole_error.push_back(n.pole_sigma_m * Vector3d(rng.normal(), rng.normal(), rng.normal()));
    for (const CrbView& v : n.views)
      noise.pixel_noise.push_back(v.pixel_sigma_px * Vector2d(rng.normal(), rng.normal()));
    const NetworkInput in = network_input(n, model.as_white(), noise);
    const NetworkResult r = network_adjust(in.cameras, in.points, in.observations, opt);
    VectorXd err(P);
    for (std::size_t c = 0; c < n.cameras.size(); ++c) {
      const VectorXd e =
          free_values(n, c, r.cameras[c].calibration.camera) - free_values(n, c, n.cameras[c].truth);
      err.segment(actual.offset[c], e.size()) = e;
    }
    f.d2_actual += err.dot(la.solve(err)) / draws;
    f.d2_believed += err.dot(lb.solve(err)) / draws;
    CameraJointCovariance one = actual;  // this draw's error as a rank-one "covariance": its mean |δX|²
    one.joint = err * err.transpose();
    e2.push_back(std::pow(intersection_sigma_m(n, one, volume), 2));
  }
  double var = 0;
  for (double x : e2) f.e2_mean += x / draws;
  for (double x : e2) var += (x - f.e2_mean) * (x - f.e2_mean) / (draws - 1);
  f.e2_sd = std::sqrt(var / draws);
  f.sandwich_m = intersection_sigma_m(n, actual, volume);
  f.believed_m = intersection_sigma_m(n, believed, volume);
  std::printf(
      "Monte Carlo, %d draws, %zu epochs: mean d² %.1f under the sandwich, %.1f under the white "
      "network's own covariance (%d parameters); intersection rms %.3f ± %.3f cm, sandwich %.3f cm, "
      "white network believes %.3f cm\n",
      draws, n.epochs.size(), f.d2_actual, f.d2_believed, f.parameters, 100 * std::sqrt(f.e2_mean),
      100 * 0.5 * f.e2_sd / std::sqrt(f.e2_mean), 100 * f.sandwich_m, 100 * f.believed_m);
  return f;
}

TEST(CorrelatedCrb, MonteCarloOfTheWhiteNetworkMatchesTheSandwich) {
  const auto t0 = std::chrono::steady_clock::now();
  constexpr int kDraws = 50;
  // The sandwich is first-order: the whitened errors are checked where the network is linear, with
  // the measured errors scaled by 0.1. (At full scale one of the 16 directions — the two cameras'
  // relative tilt, σ ~2 µrad — carries ~6× its linear variance from second-order terms of the
  // cm-sized datum errors, and the mean d² is 21; every other direction and the intersection σ
  // stay linear.)
  GaussMarkovPpk small = measured_ppk_model();
  small.white_h_m *= 0.1, small.white_v_m *= 0.1, small.gm_h_m *= 0.1, small.gm_v_m *= 0.1;
  const MonteCarloFigures lin = white_network_monte_carlo(small, kDraws, 2024);
  // d² ~ χ²_p per draw if the sandwich is right: its mean over the draws has sd √(2p/D); 4 sd.
  const double p = lin.parameters;
  EXPECT_NEAR(lin.d2_actual / p, 1.0, 4 * std::sqrt(2 / (p * kDraws)));
  // The white network's own covariance is far too small for these errors (so the test can fail).
  EXPECT_GT(lin.d2_believed / p, 3.0);
  EXPECT_NEAR(lin.e2_mean, lin.sandwich_m * lin.sandwich_m, 4 * lin.e2_sd);
  // At the measured size: the mean squared intersection error against the sandwich's, within 4 of
  // its sampling sd, and far above what the white network believes.
  const MonteCarloFigures full = white_network_monte_carlo(measured_ppk_model(), kDraws, 2025);
  EXPECT_NEAR(full.e2_mean, full.sandwich_m * full.sandwich_m, 4 * full.e2_sd);
  EXPECT_GT(std::sqrt(full.e2_mean), 3 * full.believed_m);
  std::printf("Monte Carlo test took %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

}  // namespace
}  // namespace rangecal::test
