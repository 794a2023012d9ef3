// The network with centroid errors that repeat themselves in time (optim/network/
// image_time_correlation.hpp), on simulated missions of the measured setting (tests/support/
// correlated_crb.hpp: five ascents, 2 Hz fixes, two control poles, white PPK errors at the .pos sd):
// each camera's centroid errors a first-order autoregression of 0.5 px and φ 0.9 per epoch (a
// hand label's bias that lasts seconds), stated 0.1 px, image σ estimated.
//   - weighing each camera by σ·√F, its σ hold: intersection error / predicted within [0.8, 1.25]
//     over the flight volume, z rms of f and the centres ≤ 1.25 (tests/support/network_honesty.hpp);
//   - the warnings on the image σ are the estimate's (the last solve holds them);
//   - counting every centroid as an independent look (`estimate_independent`) fails them: the σ of
//     f and the centres are too small (z rms > 1.5), so the check can fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "optim/network/image_time_correlation.hpp"
#include "support/correlated_crb.hpp"
#include "support/network_honesty.hpp"

namespace rangecal::test {
namespace {

constexpr int kMissions = 20;
constexpr double kCentroidSigmaPx = 0.5;
constexpr double kPhi = 0.9;

/// The views' pixel noise replaced by each camera's AR(1) series over its lamp views in time order
/// (stationary sd kCentroidSigmaPx per axis); the pole picks keep theirs.
void correlate_centroid_noise(const CrbNetwork& n, NetworkNoise* noise, DeterministicRandom* rng) {
  for (std::size_t c = 0; c < n.cameras.size(); ++c) {
    std::vector<std::size_t> lamp;
    for (std::size_t v = 0; v < n.views.size(); ++v)
      if (n.views[v].camera == c && n.views[v].point < n.epochs.size()) lamp.push_back(v);
    std::sort(lamp.begin(), lamp.end(), [&](std::size_t a, std::size_t b) {
      return n.epoch_time_s[n.views[a].point] < n.epoch_time_s[n.views[b].point];
    });
    const double innovation = kCentroidSigmaPx * std::sqrt(1 - kPhi * kPhi);
    Eigen::Vector2d e(rng->normal() * kCentroidSigmaPx, rng->normal() * kCentroidSigmaPx);
    for (std::size_t v : lamp) {
      noise->pixel_noise[v] = e;
      e = kPhi * e + innovation * Eigen::Vector2d(rng->normal(), rng->normal());
    }
  }
}

HonestyFigures run(bool time_correlation, std::vector<double>* factors) {
  AscentNetworkOptions a;
  a.rate_hz = 2, a.control_poles = 2, a.pixel_sigma_px = 0.1;
  const CrbNetwork stated = ascent_network(a);
  CrbNetwork truth = stated;
  for (CrbView& v : truth.views)
    if (v.point < truth.epochs.size()) v.pixel_sigma_px = kCentroidSigmaPx;
  GaussMarkovPpk ppk;
  ppk.white_h_m = 0.0085, ppk.white_v_m = 0.015;
  const CameraJointCovariance bound = cramer_rao_bound(truth, ppk_joint_covariance(truth.epoch_time_s, ppk));
  const std::vector<Eigen::Vector3d> volume = flight_volume(truth, 200, 78);
  NetworkOptions opt;
  opt.loss = RobustLoss::none;
  opt.resolve_without_outliers = false;
  opt.ppk_outlier_probability = 1e-300;
  opt.estimate_ppk_error = true;
  opt.image_time_correlation = time_correlation;
  DeterministicRandom rng(2026);
  HonestyFigures f;
  for (int d = 0; d < kMissions; ++d) {
    NetworkNoise noise = draw_network_noise(truth, ppk, &rng);
    correlate_centroid_noise(truth, &noise, &rng);
    const NetworkInput in = network_input(stated, ppk, noise);
    const NetworkResult r = network_adjust(in.cameras, in.points, in.observations, opt);
    add_mission(truth, r, bound, volume, &f);
    // The last solve holds the image σ: the warnings on how well the mission determined them are the
    // estimate's, not that solve's (whose scales have no σ).
    for (const std::string& w : r.warnings) EXPECT_EQ(w.find("nan"), std::string::npos) << w;
    if (time_correlation)
      for (double x : r.ppk_estimate->image_time_factor) factors->push_back(x);
  }
  finish(truth, bound, volume, &f);
  print(time_correlation ? "weighed by σ·√F" : "independent looks", f);
  return f;
}

TEST(ImageTimeCorrelationNetwork, WeighingByTheInflationKeepsTheSigmaHonest) {
  std::vector<double> factors;
  const HonestyFigures weighed = run(true, &factors);
  std::sort(factors.begin(), factors.end());
  // F of an AR(1) of φ 0.9: (1 + φ)/(1 − φ) = 19.
  std::printf("  F over missions and cameras: min %.1f median %.1f max %.1f\n", factors.front(),
              factors[factors.size() / 2], factors.back());
  EXPECT_GT(factors.front(), 1);
  EXPECT_GT(weighed.actual_m / weighed.predicted_m, 0.8);
  EXPECT_LT(weighed.actual_m / weighed.predicted_m, 1.25);
  EXPECT_LE(weighed.z_rms, 1.25);

  std::vector<double> unused;
  const HonestyFigures independent = run(false, &unused);
  EXPECT_GT(independent.z_rms, 1.5);
}

}  // namespace
}  // namespace rangecal::test
