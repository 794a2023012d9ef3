// The restricted likelihood's derivatives (optim/network/restricted_likelihood.hpp) on a simulated
// mission of the measured setting (tests/support/correlated_crb.hpp: five ascents, two control
// poles, correlated PPK errors):
//   - the analytic gradient of D is D's own central differences (independent: D alone, evaluated
//     at shifted parameters), for the white and the Gauss–Markov family, at points away from the
//     optimum where the gradient is large;
//   - the average information is D's curvature on average: over missions drawn from the model, at
//     the true parameters, 2·AI is the mean of the central-difference Hessian of D within its
//     spread, on and off the diagonal.
#include <gtest/gtest.h>

#include <cmath>

#include "optim/network/restricted_likelihood.hpp"
#include "support/correlated_crb.hpp"

namespace rangecal::test {
namespace {

struct Mission {
  NetworkInput input;
  NetworkLayout layout;
  NetworkParameterBlocks blocks;
  NetworkSelection selection;
};

/// One noisy mission, linearised at its starting blocks (points at their fixes), every view and
/// prior used.
Mission mission(const CrbNetwork& n, const GaussMarkovPpk& m, DeterministicRandom* rng) {
  Mission s;
  s.input = network_input(n, m, draw_network_noise(n, m, rng));
  s.layout = make_network_layout(s.input.cameras, s.input.points, s.input.observations);
  s.blocks = starting_blocks(s.layout);
  s.selection.observation.assign(s.input.observations.size(), 1);
  s.selection.prior.assign(s.input.points.size(), 1);
  return s;
}

CrbNetwork setting() {
  AscentNetworkOptions o;
  o.rate_hz = 2, o.control_poles = 2;
  return ascent_network(o);
}

double deviance_at(const RemlMission& f, const LogParameters& x, bool chain) {
  return evaluate_restricted_likelihood(f, x, chain, false).deviance;
}

TEST(RestrictedLikelihood, GradientIsTheDevianceCentralDifference) {
  const CrbNetwork n = setting();
  const GaussMarkovPpk truth = measured_ppk_model(30);
  DeterministicRandom rng(5);
  const Mission s = mission(n, truth, &rng);
  const RemlMission f = reml_mission(s.layout, s.blocks, s.selection, 2000);
  const LogParameters at_truth = log_parameters_of(network_model(truth), f.cameras());
  ASSERT_EQ(at_truth.size(), 8);
  // Away from the optimum on every parameter, so that each component is large: the PPK model's and
  // both cameras' image scales.
  LogParameters away = at_truth;
  away += (LogParameters(8) << 0.3, -0.2, 0.25, -0.3, 0.4, -0.5, 0.35, -0.25).finished();
  for (bool chain : {false, true}) {
    const RemlEvaluation e = evaluate_restricted_likelihood(f, away, chain, true);
    ASSERT_TRUE(std::isfinite(e.deviance));
    ASSERT_EQ(e.gradient.size(), 8);
    for (int i : chain ? std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7} : std::vector<int>{0, 1, 6, 7}) {
      constexpr double h = 1e-4;
      LogParameters up = away, down = away;
      up[i] += h, down[i] -= h;
      const double numeric = (deviance_at(f, up, chain) - deviance_at(f, down, chain)) / (2 * h);
      std::printf("chain %d, parameter %d: analytic %.6f, central difference %.6f\n", chain, i, e.gradient[i],
                  numeric);
      EXPECT_NEAR(e.gradient[i], numeric, 1e-4 * std::max(1.0, std::abs(numeric)));
    }
    if (!chain) {
      EXPECT_EQ(e.gradient.segment<4>(2).norm(), 0);
    }
  }
}

TEST(RestrictedLikelihood, AverageInformationIsTheDevianceCurvatureOnAverage) {
  const CrbNetwork n = setting();
  const GaussMarkovPpk truth = measured_ppk_model(30);
  const LogParameters x = log_parameters_of(network_model(truth), 2);
  DeterministicRandom rng(17);
  constexpr int kMissions = 12;
  constexpr double h = 0.02;
  using Matrix8d = Eigen::Matrix<double, 8, 8>;
  Matrix8d mean_ai = Matrix8d::Zero(), mean_h = mean_ai, sq_h = mean_ai;
  for (int d = 0; d < kMissions; ++d) {
    const Mission s = mission(n, truth, &rng);
    const RemlMission f = reml_mission(s.layout, s.blocks, s.selection, 2000);
    const RemlEvaluation e = evaluate_restricted_likelihood(f, x, true, true);
    Matrix8d H;
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j) {
        LogParameters pp = x, pm = x, mp = x, mm = x;
        pp[i] += h, pp[j] += h, pm[i] += h, pm[j] -= h, mp[i] -= h, mp[j] += h, mm[i] -= h, mm[j] -= h;
        H(i, j) = (deviance_at(f, pp, true) - deviance_at(f, pm, true) - deviance_at(f, mp, true) +
                   deviance_at(f, mm, true)) /
                  (4 * h * h);
      }
    mean_ai += 2 * e.information / kMissions, mean_h += H / kMissions, sq_h += H.cwiseProduct(H) / kMissions;
  }
  const Matrix8d se = ((sq_h - mean_h.cwiseProduct(mean_h)) / (kMissions - 1)).cwiseMax(0).cwiseSqrt();
  for (int i = 0; i < 8; ++i) {
    std::printf("parameter %d: 2·AI %.2f, Hessian %.2f ± %.2f\n", i, mean_ai(i, i), mean_h(i, i), se(i, i));
    for (int j = 0; j < i; ++j)
      std::printf("    (%d, %d): 2·AI %.2f, Hessian %.2f ± %.2f\n", i, j, mean_ai(i, j), mean_h(i, j),
                  se(i, j));
    // The diagonal: within 4 standard errors of the mean Hessian, or 10 % of it.
    EXPECT_LT(std::abs(mean_ai(i, i) - mean_h(i, i)), std::max(4 * se(i, i), 0.1 * mean_h(i, i)));
    // Off the diagonal: within 4 standard errors, or 10 % of the diagonal's geometric mean.
    for (int j = 0; j < i; ++j)
      EXPECT_LT(std::abs(mean_ai(i, j) - mean_h(i, j)),
                std::max(4 * se(i, j), 0.1 * std::sqrt(mean_h(i, i) * mean_h(j, j))))
          << i << ", " << j;
  }
}

}  // namespace
}  // namespace rangecal::test
