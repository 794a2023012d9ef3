// The robust losses (optim/estimation/robust_loss.hpp) against their formulas: Huber ρ(s) = s below a²,
// 2a√s − a² above; Cauchy ρ(s) = a²·ln(1 + s/a²); none is plain least squares (no loss).
#include "optim/estimation/robust_loss.hpp"

#include <ceres/loss_function.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

namespace rangecal {
namespace {

double rho(RobustLoss kind, double scale, double s) {
  const std::unique_ptr<ceres::LossFunction> loss(new_robust_loss(kind, scale));
  double r[3];
  loss->Evaluate(s, r);
  return r[0];
}

TEST(RobustLoss, HuberAndCauchyFollowTheirFormulas) {
  const double a = 3.0;
  EXPECT_NEAR(rho(RobustLoss::huber, a, 4.0), 4.0, 1e-12);                   // below a² = 9
  EXPECT_NEAR(rho(RobustLoss::huber, a, 25.0), 2 * a * 5.0 - a * a, 1e-12);  // = 21
  EXPECT_NEAR(rho(RobustLoss::cauchy, a, 25.0), a * a * std::log(1 + 25.0 / 9), 1e-12);
  EXPECT_EQ(new_robust_loss(RobustLoss::none, a), nullptr);
}

TEST(RobustLoss, Names) {
  EXPECT_EQ(std::string(to_string(RobustLoss::none)), "none");
  EXPECT_EQ(std::string(to_string(RobustLoss::huber)), "huber");
  EXPECT_EQ(std::string(to_string(RobustLoss::cauchy)), "cauchy");
}

}  // namespace
}  // namespace rangecal
