#include "support/bundle_synthetic.hpp"

#include <random>
#include <stdexcept>

#include "support/synthetic_camera.hpp"

namespace rangecal::test {

Camera narrow_fov_camera(double k1_per_mm2) {
  return range_camera_at("cam_synthetic", {0, 0, 1.5}, {40, 48, 22}, k1_per_mm2, {641.3, 398.6});
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
