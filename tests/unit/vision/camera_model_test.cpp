#include "vision/camera/camera_model.hpp"

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <random>
#include <utility>

namespace rangecal {
namespace {

Camera paper_like_camera() {
  // Seed 002 Table 1 (identification-target column): 1280×800, 20 µm, f 136 mm, k1 −3.4e−4 mm⁻².
  Camera c;
  c.intr.width_px = 1280;
  c.intr.height_px = 800;
  c.intr.dx_mm = c.intr.dy_mm = 0.020;
  c.intr.f_mm = 136.12;
  c.intr.sx = 0.9966;
  c.intr.u0_px = 640.27;
  c.intr.v0_px = 399.67;
  c.intr.dist.k1 = -3.443e-4;
  c.pose.R << -0.8273, 0.0006, 0.5617, 0.0151, -0.9994, 0.0307, 0.5614, 0.0339, 0.8268;
  // Orthonormalise the printed (4-digit) matrix.
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(c.pose.R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  c.pose.R = svd.matrixU() * svd.matrixV().transpose();
  c.pose.T << -4.2194, -3.0224, 63.8206;
  return c;
}

TEST(CameraModel, ProjectInvertsDistortionToMicroPixels) {
  Camera c = paper_like_camera();
  c.intr.dist = {-3.4e-4, 2e-7, -1e-10, 3e-5, -2e-5, 1e-4, -5e-5};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0, 1);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector2d uv(U(rng) * 1279, U(rng) * 799);
    // Back-project the pixel to a world point 60–70 m away, then project it again.
    const Eigen::Vector3d ray = pixel_ray_world(c, uv);
    const Eigen::Vector3d X = c.pose.center() + ray * (60 + 10 * U(rng));
    Eigen::Vector2d back;
    ASSERT_TRUE(project(c, X, &back));
    EXPECT_LT((back - uv).norm(), 1e-6) << uv.transpose();
  }
}

TEST(CameraModel, K1OnlyIsTsaiEquation7) {
  // xu = xd (1 + k1 r²): check one point by hand.
  const double d[7] = {-3e-4, 0, 0, 0, 0, 0, 0};
  double xu, yu;
  undistort_sensor(d, 6.0, -4.0, &xu, &yu);
  const double r2 = 36.0 + 16.0;
  EXPECT_DOUBLE_EQ(xu, 6.0 * (1 - 3e-4 * r2));
  EXPECT_DOUBLE_EQ(yu, -4.0 * (1 - 3e-4 * r2));
}

TEST(CameraModel, PoseConventionsAndPixelOrigin) {
  // Camera at C looking north (world +y) with x right = east, y down = −up.
  Camera c;
  c.intr = {1280, 800, 0.02, 0.02, 100.0, 1.0, 639.5, 399.5, {}};
  c.pose.R << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  const Eigen::Vector3d C(10, -50, 2);
  c.pose.T = -c.pose.R * C;
  EXPECT_LT((c.pose.center() - C).norm(), 1e-12);
  Eigen::Vector2d uv;
  ASSERT_TRUE(project(c, C + Eigen::Vector3d(0, 100, 0), &uv));
  EXPECT_NEAR(uv.x(), 639.5, 1e-9);
  EXPECT_NEAR(uv.y(), 399.5, 1e-9);
  // A point 1 m east and 1 m up at 100 m: u grows (right), v shrinks (up is image-up).
  ASSERT_TRUE(project(c, C + Eigen::Vector3d(1, 100, 1), &uv));
  EXPECT_NEAR(uv.x(), 639.5 + 100.0 * 1 / 100 / 0.02, 1e-9);
  EXPECT_NEAR(uv.y(), 399.5 - 100.0 * 1 / 100 / 0.02, 1e-9);
  EXPECT_FALSE(project(c, C - Eigen::Vector3d(0, 100, 0), &uv));  // behind the camera
}

TEST(CameraModel, AutodiffDerivativesMatchFiniteDifferences) {
  using J = ceres::Jet<double, 4>;
  const Camera c = paper_like_camera();
  const Eigen::Vector3d xc(1.3, -0.8, 64.0);
  const auto d = c.intr.dist.as_array();
  J intr[4] = {J(c.intr.f_mm, 0), J(c.intr.sx, 1), J(c.intr.u0_px, 2), J(c.intr.v0_px, 3)};
  J dj[7];
  for (int i = 0; i < 7; ++i) dj[i] = J(d[i]);
  const J xcj[3] = {J(xc.x()), J(xc.y()), J(xc.z())};
  J u, v;
  ASSERT_TRUE(project_camera_point(intr, dj, c.intr.dx_mm, c.intr.dy_mm, xcj, &u, &v));
  const double base[4] = {c.intr.f_mm, c.intr.sx, c.intr.u0_px, c.intr.v0_px};
  for (int k = 0; k < 4; ++k) {
    double p[4] = {base[0], base[1], base[2], base[3]}, m[4] = {base[0], base[1], base[2], base[3]};
    const double h = 1e-6 * std::max(1.0, std::abs(base[k]));
    p[k] += h;
    m[k] -= h;
    double up, vp, um, vm;
    project_camera_point(p, d.data(), c.intr.dx_mm, c.intr.dy_mm, xc.data(), &up, &vp);
    project_camera_point(m, d.data(), c.intr.dx_mm, c.intr.dy_mm, xc.data(), &um, &vm);
    EXPECT_NEAR(u.v[k], (up - um) / (2 * h), 1e-5 * std::max(1.0, std::abs(u.v[k])));
    EXPECT_NEAR(v.v[k], (vp - vm) / (2 * h), 1e-5 * std::max(1.0, std::abs(v.v[k])));
  }
}

// distortion_jacobian, the one written-out ∂(xd + Δ(xd))/∂xd that Newton's inverse, the Jet inverse
// and the optimiser's projection derivatives share, against central differences of undistort_sensor
// with all seven terms, at points over a 25.6 × 16 mm sensor.
TEST(CameraModel, DistortionJacobianMatchesFiniteDifferences) {
  const double d[7] = {-3.4e-4, 2.1e-6, -1.3e-8, 4e-5, -6e-5, 2e-4, -1.5e-4};
  const double h = 1e-5;
  for (const auto& [x, y] :
       {std::pair{0.0, 0.0}, std::pair{12.0, -7.5}, std::pair{-9.3, 6.1}, std::pair{3.3, 7.9}}) {
    double j[4];
    distortion_jacobian(d, x, y, j);
    double xp, yp, xm, ym;
    undistort_sensor(d, x + h, y, &xp, &yp);
    undistort_sensor(d, x - h, y, &xm, &ym);
    EXPECT_NEAR(j[0], (xp - xm) / (2 * h), 1e-8) << x << ", " << y;
    EXPECT_NEAR(j[2], (yp - ym) / (2 * h), 1e-8) << x << ", " << y;
    undistort_sensor(d, x, y + h, &xp, &yp);
    undistort_sensor(d, x, y - h, &xm, &ym);
    EXPECT_NEAR(j[1], (xp - xm) / (2 * h), 1e-8) << x << ", " << y;
    EXPECT_NEAR(j[3], (yp - ym) / (2 * h), 1e-8) << x << ", " << y;
  }
  // At the principal point only a1, a2 act: J = [[1, 0], [a1, 1 + a2]].
  double j0[4];
  distortion_jacobian(d, 0.0, 0.0, j0);
  EXPECT_EQ(j0[0], 1.0);
  EXPECT_EQ(j0[1], 0.0);
  EXPECT_EQ(j0[2], d[5]);
  EXPECT_EQ(j0[3], 1 + d[6]);
}

}  // namespace
}  // namespace rangecal
