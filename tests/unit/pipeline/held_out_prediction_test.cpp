// The held-out check (pipeline/steps/held_out_prediction.hpp) on simulated missions of the measured
// setting (tests/support/correlated_crb.hpp: five ascents, 2 Hz fixes, two control poles) with
// correlated PPK errors (τ 30 s) and lamp centroids scattering 0.5 px where 0.1 px is stated:
//   - the network with the PPK model and the image σ estimated predicts the held-out epochs with a
//     σ that holds (pooled z rms within [0.8, 1.25]);
//   - a model that understates the fixes' error (white, 0.3 × their sd) fails on the held-out epochs
//     (z rms above 2) and scores worse in every mission: the check can tell a σ that does not hold.
// The held-out epochs are compared with their fixes, whose error (2 cm here) dominates the
// triangulation's (a few mm): the check judges the PPK model far more than the image σ (holding the
// stated 0.1 px under the true PPK model gives z rms 1.08 here, printed).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "pipeline/steps/held_out_prediction.hpp"
#include "support/correlated_crb.hpp"

namespace rangecal::test {
namespace {

constexpr int kMissions = 8;

TEST(HeldOutPrediction, EstimatedModelHoldsAndUnderstatedFixesFail) {
  AscentNetworkOptions o;
  o.rate_hz = 2, o.control_poles = 2, o.pixel_sigma_px = 0.1;
  const CrbNetwork stated = ascent_network(o);
  CrbNetwork truth = stated;
  for (CrbView& v : truth.views)
    if (v.point < truth.epochs.size()) v.pixel_sigma_px = 0.5;
  const GaussMarkovPpk ppk = measured_ppk_model(30);
  NetworkOptions estimated;
  estimated.estimate_ppk_error = true;
  estimated.estimate_image_sigma = true;
  NetworkOptions held;  // the true PPK model, the stated image σ
  held.ppk_error = network_model(ppk);
  held.estimate_image_sigma = false;
  NetworkOptions understated;
  understated.ppk_error.white_scale_h = understated.ppk_error.white_scale_v = 0.3;
  understated.estimate_image_sigma = false;
  DeterministicRandom rng(4242);
  double m_est = 0, m_held = 0, m_under = 0, n_est = 0, n_held = 0, n_under = 0;
  int estimated_better = 0;
  for (int d = 0; d < kMissions; ++d) {
    const NetworkInput in = network_input(stated, ppk, draw_network_noise(truth, ppk, &rng));
    const std::vector<HeldOutScore> s = score_held_out_blocks(
        in.cameras, in.points, in.observations,
        {{"estimated", estimated, {}}, {"stated", held, {}}, {"understated", understated, {}}});
    for (const HeldOutScore& x : s) ASSERT_TRUE(x.scored) << x.candidate << ": " << x.why;
    std::printf(
        "mission %d: estimated z %.2f rms %.1f mm score %.2f | stated z %.2f rms %.1f mm score %.2f (%zu "
        "epochs)\n",
        d, s[0].z_rms, 1e3 * s[0].rms_m, s[0].score, s[1].z_rms, 1e3 * s[1].rms_m, s[1].score, s[0].epochs);
    m_est += s[0].z_rms * s[0].z_rms * s[0].epochs, n_est += s[0].epochs;
    m_held += s[1].z_rms * s[1].z_rms * s[1].epochs, n_held += s[1].epochs;
    m_under += s[2].z_rms * s[2].z_rms * s[2].epochs, n_under += s[2].epochs;
    estimated_better += s[0].score < s[2].score;
  }
  const double z_est = std::sqrt(m_est / n_est), z_held = std::sqrt(m_held / n_held),
               z_under = std::sqrt(m_under / n_under);
  std::printf(
      "pooled z rms: estimated %.2f, stated σ held %.2f, understated fixes %.2f; the estimate scores "
      "better than the understated in %d of %d\n",
      z_est, z_held, z_under, estimated_better, kMissions);
  EXPECT_GE(z_est, 0.8);
  EXPECT_LE(z_est, 1.25);
  EXPECT_GT(z_under, 2.0);
  EXPECT_EQ(estimated_better, kMissions);
}

}  // namespace
}  // namespace rangecal::test
