#include "support/bundle_synthetic.hpp"

#include <random>
#include <stdexcept>

namespace rangecal::test {

Eigen::Matrix3d look_at(const Eigen::Vector3d& C, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - C).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();  // right
  const Eigen::Vector3d y = z.cross(x);                                      // down
  Eigen::Matrix3d R;
  R.row(0) = x.transpose();
  R.row(1) = y.transpose();
  R.row(2) = z.transpose();
  return R;
}

Camera narrow_fov_camera(double k1_per_mm2) {
  Camera c;
  c.id = "cam_synthetic";
  c.intr.width_px = 1280;
  c.intr.height_px = 800;
  c.intr.dx_mm = c.intr.dy_mm = 0.020;
  c.intr.f_mm = 135.0;
  c.intr.sx = 1.0;
  c.intr.u0_px = 641.3;
  c.intr.v0_px = 398.6;
  c.intr.dist.k1 = k1_per_mm2;
  const Eigen::Vector3d C(0, 0, 1.5);
  c.pose.R = look_at(C, Eigen::Vector3d(40, 48, 22));
  c.pose.T = -c.pose.R * C;
  return c;
}

SyntheticPoints synthetic_points(const Camera& cam, int n, std::uint64_t seed, double depth_min,
                                 double depth_max) {
  std::mt19937_64 rng(seed);
  auto uni = [&](double a, double b) { return a + (b - a) * (static_cast<double>(rng() >> 11) * 0x1.0p-53); };
  SyntheticPoints s;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d uv(uni(20, cam.intr.width_px - 21), uni(20, cam.intr.height_px - 21));
    const Eigen::Vector2d su = pixel_to_undistorted_sensor(cam.intr, uv);
    const double depth = uni(depth_min, depth_max);
    const Eigen::Vector3d xc(su.x() / cam.intr.f_mm * depth, su.y() / cam.intr.f_mm * depth, depth);
    const Eigen::Vector3d Xw = cam.pose.R.transpose() * (xc - cam.pose.T);
    Eigen::Vector2d p;
    if (!project(cam, Xw, &p)) throw std::runtime_error("synthetic point does not project");
    s.world.push_back(Xw);
    s.pixel.push_back(p);
  }
  return s;
}

}  // namespace rangecal::test
