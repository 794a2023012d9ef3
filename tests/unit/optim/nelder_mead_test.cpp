// Nelder–Mead (optim/search/nelder_mead.hpp) on functions whose minimum is known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "optim/search/nelder_mead.hpp"

namespace rangecal {
namespace {

TEST(NelderMead, FindsTheRosenbrockValley) {
  const auto rosenbrock = [](const Eigen::VectorXd& x) {
    return 100 * std::pow(x[1] - x[0] * x[0], 2) + std::pow(1 - x[0], 2);
  };
  const NelderMeadResult r =
      nelder_mead(rosenbrock, Eigen::Vector2d(-1.2, 1), Eigen::Vector2d(0.5, 0.5), 1e-14, 5000);
  EXPECT_NEAR(r.x[0], 1, 1e-4);
  EXPECT_NEAR(r.x[1], 1, 2e-4);
  EXPECT_LT(r.value, 1e-8);
  EXPECT_LT(r.evaluations, 5000);
}

TEST(NelderMead, MinimisesAQuadraticInSixDimensionsAndAvoidsInfeasiblePoints) {
  // f = Σ (i+1)·(x_i − i)², +∞ where x_0 < −1 (the simplex steps there at the start).
  const auto f = [](const Eigen::VectorXd& x) {
    if (x[0] < -1) return std::numeric_limits<double>::infinity();
    double s = 0;
    for (int i = 0; i < 6; ++i) s += (i + 1) * (x[i] - i) * (x[i] - i);
    return s;
  };
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(6);
  x0[0] = -0.9;
  Eigen::VectorXd step = Eigen::VectorXd::Constant(6, 0.5);
  step[0] = -0.5;
  NelderMeadResult r = nelder_mead(f, x0, step, 1e-16, 20000);
  r = nelder_mead(f, r.x, Eigen::VectorXd::Constant(6, 0.1), 1e-16, 20000);  // a restart, as the estimator
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(r.x[i], i, 1e-5) << i;
}

TEST(NelderMead, StopsAtTheEvaluationBudget) {
  int calls = 0;
  const auto f = [&](const Eigen::VectorXd& x) {
    ++calls;
    return x.squaredNorm();
  };
  const NelderMeadResult r = nelder_mead(f, Eigen::Vector3d(5, 5, 5), Eigen::Vector3d(1, 1, 1), 0, 50);
  EXPECT_EQ(r.evaluations, calls);
  EXPECT_LE(r.evaluations, 50 + 4);  // the last iteration may finish a shrink of the simplex
}

}  // namespace
}  // namespace rangecal
