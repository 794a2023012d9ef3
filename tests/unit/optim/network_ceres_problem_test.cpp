// The network's Ceres problem is built once and solved twice (optim/network/network_ceres_problem.hpp):
// between the robust and the least-squares solve, residuals leave by being switched off, a point
// left with one ray becomes that camera's single-view residual, and a point left with nothing is
// held. Held here against a problem built afresh for the second selection, from the same start:
// the same cameras and points to rounding.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "optim/network/network_ceres_problem.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

struct Network {
  std::vector<NetworkCamera> cameras;
  std::vector<NetworkPoint> points;
  std::vector<NetworkObservation> observations;
};

/// Three range cameras 64 m round a lamp volume, 300 epochs with 1 cm PPK noise, 0.05 px centroids;
/// the cameras start off the truth (3 cm, 0.3 mrad, f × 1.002).
Network make_network() {
  Network n;
  const Vector3d aim(0, 0, 20);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> N01;
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<Camera> truth;
  for (int c = 0; c < 3; ++c) {
    const double a = 2 * M_PI * c / 3 + 0.3;
    truth.push_back(test::range_camera_at("cam" + std::to_string(c + 1),
                                          aim + Vector3d(64 * std::cos(a), 64 * std::sin(a), -18.5), aim));
    NetworkCamera nc;
    nc.initial = truth.back();
    nc.initial.intr.f_mm *= 1.002;
    const Vector3d C = truth.back().pose.center() + Vector3d(0.03, -0.02, 0.03);
    nc.initial.pose.R =
        Eigen::AngleAxisd(3e-4, Vector3d(1, -1, 0.5).normalized()).toRotationMatrix() * truth.back().pose.R;
    nc.initial.pose.T = -nc.initial.pose.R * C;
    nc.options.free = {"f", "k1", "pose"};
    n.cameras.push_back(nc);
  }
  for (int k = 0; k < 300; ++k) {
    const Vector3d X = aim + Vector3d(2.5 * U(rng), 2.5 * U(rng), 2.0 * U(rng));
    NetworkPoint p;
    p.prior_cov = Matrix3d::Identity() * 1e-4;
    p.prior_enu = X + 0.01 * Vector3d(N01(rng), N01(rng), N01(rng));
    for (std::size_t c = 0; c < truth.size(); ++c) {
      NetworkObservation o;
      if (!project(truth[c], X, &o.pixel) || !inside_image(truth[c].intr, o.pixel)) continue;
      o.camera = c;
      o.point = n.points.size();
      o.pixel += 0.05 * Vector2d(N01(rng), N01(rng));
      o.pixel_sigma_px = 0.05;
      n.observations.push_back(o);
    }
    n.points.push_back(p);
  }
  return n;
}

NetworkParameterBlocks starting_blocks(const NetworkLayout& l) {
  NetworkParameterBlocks b;
  for (const Camera& s : l.starts) b.cameras.push_back(BundleParameterBlocks::from_camera(s));
  for (const NetworkPoint& p : *l.points)
    b.points.push_back({p.prior_enu.x(), p.prior_enu.y(), p.prior_enu.z()});
  return b;
}

TEST(NetworkCeresProblem, SecondSolveInPlaceEqualsAFreshProblem) {
  const Network n = make_network();
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
