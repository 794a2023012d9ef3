// The network's Ceres problem is built once and solved twice (optim/network/network_ceres_problem.hpp):
// between the robust and the least-squares solve, residuals leave by being switched off, a point
// left with one ray becomes that camera's single-view residual, and a point left with nothing is
// held. Held here against a problem built afresh for the second selection, from the same start:
// the same cameras and points to rounding.
#include <gtest/gtest.h>

#include <cmath>

#include "optim/network/network_ceres_problem.hpp"
#include "support/synthetic_network.hpp"

namespace rangecal {
namespace {

TEST(NetworkCeresProblem, SecondSolveInPlaceEqualsAFreshProblem) {
  const test::SyntheticNetwork n = test::synthetic_network(3, 300, 5);
  const NetworkLayout l = make_network_layout(n.cameras, n.points, n.observations);
  NetworkParameterBlocks b = starting_blocks(l);
  NetworkSelection sel{
      std::vector<char>(n.observations.size(), 1), std::vector<char>(n.points.size(), 1), {}, {}};
  refresh_single_view(l, b, &sel);
  NetworkCeresProblem problem(l, &b, sel);
  problem.solve(RobustLoss::huber, 3.0, 1e-6, 50, 1);

  // Point 0 keeps one ray (becomes single-view), point 1 loses its prior, point 2 loses everything.
  ASSERT_GE(l.by_point[0].size(), 2u);
  ASSERT_GE(l.by_point[1].size(), 2u);
  for (std::size_t j = 1; j < l.by_point[0].size(); ++j) sel.observation[l.by_point[0][j]] = 0;
  sel.prior[1] = 0;
  sel.prior[2] = 0;
  for (std::size_t i : l.by_point[2]) sel.observation[i] = 0;
  refresh_single_view(l, b, &sel);
  ASSERT_TRUE(sel.single_view[0]);

  NetworkParameterBlocks fresh_blocks = b;
  NetworkCeresProblem fresh(l, &fresh_blocks, sel);
  problem.select(sel);
  const std::array<double, 3> held = b.points[2];
  problem.solve(RobustLoss::none, 3.0, 1e-12, 50, 1);
  fresh.solve(RobustLoss::none, 3.0, 1e-12, 50, 1);

  for (std::size_t c = 0; c < b.cameras.size(); ++c) {
    const Camera a = b.cameras[c].to_camera(l.starts[c]), f = fresh_blocks.cameras[c].to_camera(l.starts[c]);
    EXPECT_NEAR(a.intr.f_mm, f.intr.f_mm, 1e-9 * f.intr.f_mm) << c;
    EXPECT_NEAR(a.intr.dist.k1, f.intr.dist.k1, 1e-9 * std::abs(f.intr.dist.k1) + 1e-15) << c;
    EXPECT_LT((a.pose.center() - f.pose.center()).norm(), 1e-8) << c;
    EXPECT_LT((a.pose.R - f.pose.R).norm(), 1e-10) << c;
    // The second selection moved the cameras: the comparison is not of two untouched starts.
    EXPECT_GT(std::abs(a.intr.f_mm - n.cameras[c].initial.intr.f_mm), 1e-3) << c;
  }
  for (std::size_t k = 1; k < b.points.size(); ++k)
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(b.points[k][a], fresh_blocks.points[k][a], 1e-9) << k;
  EXPECT_EQ(b.points[2], held);  // held constant, with nothing left to determine it
}

}  // namespace
}  // namespace rangecal
