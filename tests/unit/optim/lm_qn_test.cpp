// LM / quasi-Newton hybrid (optim/search/lm_qn, seed 000 §3): converges to the same minimum as plain LM
// on Rosenbrock (zero residual: stays LM) and on a noisy seed-000-like camera resection (non-zero
// residual: switches to QN), reporting iteration counts of both.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "config/error.hpp"
#include "optim/search/lm_qn.hpp"
#include "support/bundle_synthetic.hpp"
#include "support/synthetic_camera.hpp"

namespace rangecal {
namespace {

using Eigen::MatrixXd;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::VectorXd;

bool rosenbrock(const VectorXd& x, VectorXd* r) {
  r->resize(2);
  (*r)[0] = 10 * (x[1] - x[0] * x[0]);
  (*r)[1] = 1 - x[0];
  return true;
}
bool rosenbrock_jacobian(const VectorXd& x, MatrixXd* J) {
  J->resize(2, 2);
  *J << -20 * x[0], 10, -1, 0;
  return true;
}

TEST(LmQn, RosenbrockSameMinimumAsLm) {
  const VectorXd x0 = (VectorXd(2) << -1.2, 1.0).finished();
  LmQnOptions plain;
  plain.allow_qn = false;
  const auto lm = lm_qn_minimise(rosenbrock, rosenbrock_jacobian, x0, plain);
  const auto hy = lm_qn_minimise(rosenbrock, rosenbrock_jacobian, x0);
  std::printf("Rosenbrock: LM %d iterations, LM-QN %d (%d LM, %d QN) %s\n", lm.iterations, hy.iterations,
              hy.lm_steps, hy.qn_steps, hy.step_kinds.c_str());
  EXPECT_TRUE(lm.converged);
  EXPECT_TRUE(hy.converged);
  EXPECT_NEAR(lm.x[0], 1.0, 1e-8);
  EXPECT_NEAR(hy.x[0], 1.0, 1e-8);
  EXPECT_NEAR(hy.x[1], 1.0, 1e-8);
  EXPECT_EQ(hy.qn_steps, 0);  // zero residual: ‖g‖∞ never falls below 0.02·F, LM is quadratic
}

TEST(LmQn, NumericJacobianMatchesAnalytic) {
  const VectorXd x = (VectorXd(2) << 0.3, -0.7).finished();
  MatrixXd Jn, Ja;
  ASSERT_TRUE(numeric_jacobian(rosenbrock, x, 1e-6, VectorXd(), &Jn));
  rosenbrock_jacobian(x, &Ja);
  EXPECT_LT((Jn - Ja).norm(), 1e-7);
  // The solver with the numeric Jacobian reaches the same point and counts the extra calls.
  const auto r = lm_qn_minimise(rosenbrock, nullptr, (VectorXd(2) << -1.2, 1.0).finished());
  EXPECT_NEAR(r.x[0], 1.0, 1e-7);
  EXPECT_GT(r.residual_evaluations, 4 * r.jacobian_evaluations);
}

// Seed-000-like camera problem: one camera, 3-D control points, f, u0, v0, k1, k2, p1, p2 and pose
// from 0.5 px noisy pixels. Parameters are searched as x = (θ − θ0)/s (s = typical magnitudes) so
// μ·I is meaningful in every coordinate.
struct CameraProblem {
  Camera truth, start;
  std::vector<Vector3d> X;
  std::vector<Vector2d> uv;
  VectorXd scale;
  Camera camera(const VectorXd& x) const {
    Camera c = start;
    const VectorXd th = x.cwiseProduct(scale);
    c.intr.f_mm += th[0];
    c.intr.u0_px += th[1];
    c.intr.v0_px += th[2];
    c.intr.dist.k1 += th[3];
    c.intr.dist.k2 += th[4];
    c.intr.dist.p1 += th[5];
    c.intr.dist.p2 += th[6];
    const Vector3d w = th.segment<3>(7);
    const Eigen::Matrix3d dR = w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix()
                                            : Eigen::Matrix3d::Identity();
    const Vector3d C = start.pose.center() + th.segment<3>(10);
    c.pose.R = dR * start.pose.R;
    c.pose.T = -c.pose.R * C;
    return c;
  }
  bool residual(const VectorXd& x, VectorXd* r) const {
    return test::reprojection_residuals(camera(x), X, uv, r);
  }
};

CameraProblem make_camera_problem() {
  CameraProblem P;
  Camera& t = P.truth;
  t.intr.width_px = 1280, t.intr.height_px = 800, t.intr.dx_mm = t.intr.dy_mm = 0.02;
  t.intr.f_mm = 35, t.intr.u0_px = 652, t.intr.v0_px = 391;
  t.intr.dist.k1 = 3e-4, t.intr.dist.k2 = -4e-7, t.intr.dist.p1 = 5e-5, t.intr.dist.p2 = -3e-5;
  const Vector3d C(0, 0, 1.5);
  t.pose.R = test::look_at_pose(C, Vector3d(10, 30, 8)).R;
  t.pose.T = -t.pose.R * C;
  const auto pts = test::synthetic_points(t, 120, 77, 20, 45);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> N01;
  P.X = pts.world;
  for (const auto& p : pts.pixel) P.uv.push_back(p + 0.5 * Vector2d(N01(rng), N01(rng)));
  P.start = t;  // a DLT-quality start: f 3 % off, no distortion, pose off by mrad / dm
  P.start.intr.f_mm *= 1.03;
  P.start.intr.u0_px = 640, P.start.intr.v0_px = 400;
  P.start.intr.dist = Distortion{};
  const Vector3d C0 = C + Vector3d(0.2, -0.3, 0.1);
  P.start.pose.R = Eigen::AngleAxisd(0.01, Vector3d(1, 2, 3).normalized()).toRotationMatrix() * t.pose.R;
  P.start.pose.T = -P.start.pose.R * C0;
  P.scale.resize(13);
  P.scale << 1, 10, 10, 1e-4, 1e-7, 1e-5, 1e-5, 1e-3, 1e-3, 1e-3, 0.1, 0.1, 0.1;
  return P;
}

TEST(LmQn, CameraProblemSameMinimumAsLmAndUsesQn) {
  const CameraProblem P = make_camera_problem();
  const ResidualFunction r = [&](const VectorXd& x, VectorXd* res) { return P.residual(x, res); };
  LmQnOptions plain;
  plain.allow_qn = false;
  const VectorXd x0 = VectorXd::Zero(13);
  const auto lm = lm_qn_minimise(r, nullptr, x0, plain);
  const auto hy = lm_qn_minimise(r, nullptr, x0);
  std::printf(
      "camera: LM %d iterations (%ld r-evals), LM-QN %d (%d LM, %d QN, %d→QN, %d→LM; %ld r-evals) %s\n",
      lm.iterations, lm.residual_evaluations, hy.iterations, hy.lm_steps, hy.qn_steps, hy.switches_to_qn,
      hy.switches_to_lm, hy.residual_evaluations, hy.step_kinds.c_str());
  EXPECT_TRUE(lm.converged) << lm.stop_reason;
  EXPECT_TRUE(hy.converged) << hy.stop_reason;
  EXPECT_GT(hy.qn_steps, 0);
  EXPECT_NEAR(hy.F, lm.F, 1e-9 * lm.F);
  // Same minimum: every parameter agrees to far below its noise-induced uncertainty.
  const Camera a = P.camera(lm.x), b = P.camera(hy.x);
  EXPECT_NEAR(a.intr.f_mm, b.intr.f_mm, 1e-6);
  EXPECT_NEAR(a.intr.u0_px, b.intr.u0_px, 1e-4);
  EXPECT_LT((a.pose.center() - b.pose.center()).norm(), 1e-6);
  // And it is the truth within the noise (0.5 px over 120 points).
  EXPECT_NEAR(b.intr.f_mm, P.truth.intr.f_mm, 0.1);
  EXPECT_NEAR(std::sqrt(2 * hy.F / (2 * 120 - 13)), 0.5, 0.07);
}

TEST(LmQn, NonFiniteStartIsACalibrationError) {
  const ResidualFunction bad = [](const VectorXd&, VectorXd* r) {
    *r = VectorXd::Constant(2, std::nan(""));
    return true;
  };
  try {
    lm_qn_minimise(bad, nullptr, VectorXd::Zero(2));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::calibration);
  }
}

}  // namespace
}  // namespace rangecal
