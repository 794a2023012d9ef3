#include "vision/camera/distortion_validity.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "config/number_format.hpp"

namespace rangecal {
namespace {

/// The coefficient whose term is largest at distorted sensor radius r (mm): the one to name.
int dominant_term(const Distortion& d, double r) {
  const std::array<double, 7> size = {
      std::abs(d.k1) * r * r * r, std::abs(d.k2) * std::pow(r, 5), std::abs(d.k3) * std::pow(r, 7),
      3 * std::abs(d.p1) * r * r, 3 * std::abs(d.p2) * r * r,      std::abs(d.a1) * r,
      std::abs(d.a2) * r};
  return static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
}

std::string g(double x) {
  return format_number("%.4g", x);
}

}  // namespace

bool distortion_is_physical(const CameraIntrinsics& in, DistortionFault* fault) {
  const Distortion& d = in.dist;
  const std::array<double, 7> da = d.as_array();
  const auto sensor = [&](double u, double v) {
    Eigen::Vector2d x;
    pixel_to_sensor(in.sx, in.u0_px, in.v0_px, in.dx_mm, in.dy_mm, u, v, &x.x(), &x.y());
    return x;
  };
  const double u_lo = -0.5, u_hi = in.width_px - 0.5, v_lo = -0.5, v_hi = in.height_px - 0.5;
  double r_corner = 0;
  for (double u : {u_lo, u_hi})
    for (double v : {v_lo, v_hi}) r_corner = std::max(r_corner, sensor(u, v).norm());
  // The radial part alone, densely (every r_corner / 2000); the grid below catches the rest.
  constexpr int kRadialSteps = 2000;
  for (int i = 0; i <= kRadialSteps; ++i) {
    const double r = r_corner * i / kRadialSteps, s = r * r;
    const double slope = 1 + 3 * d.k1 * s + 5 * d.k2 * s * s + 7 * d.k3 * s * s * s;
    if (!(slope > 0)) {
      *fault = {dominant_term(d, r), "the radial distortion folds at " + g(r) +
                                         " mm from the principal point (inside the image, whose farthest "
                                         "corner is at " +
                                         g(r_corner) + " mm): d/dr [r (1 + k1 r² + k2 r⁴ + k3 r⁶)] = " +
                                         g(slope) + " there, so distinct points share one image"};
      return false;
    }
  }
  constexpr int kGrid = 64;
  for (int i = 0; i <= kGrid; ++i)
    for (int k = 0; k <= kGrid; ++k) {
      const double u = u_lo + (u_hi - u_lo) * i / kGrid, v = v_lo + (v_hi - v_lo) * k / kGrid;
      const Eigen::Vector2d x = sensor(u, v);
      double j[4], dx = 0, dy = 0;
      distortion_jacobian(da.data(), x.x(), x.y(), j);
      distortion_delta(da.data(), x.x(), x.y(), &dx, &dy);
      const double det = j[0] * j[3] - j[1] * j[2], shift = std::hypot(dx, dy), r = x.norm();
      const std::string at = " at pixel (" + g(u) + ", " + g(v) + ")";
      if (!(det > 0)) {
        *fault = {dominant_term(d, r), "the distortion is not invertible" + at + ": det J = " + g(det) +
                                           " (the map distorted → undistorted folds inside the image)"};
        return false;
      }
      if (!(shift <= kMaxDistortionShare * r + 1e-12)) {
        *fault = {dominant_term(d, r), "the distortion moves the image point" + at + " by " + g(shift) +
                                           " mm, " + g(shift / std::max(r, 1e-300)) +
                                           " times its distance from the principal point (limit " +
                                           g(kMaxDistortionShare) + ")"};
        return false;
      }
    }
  return true;
}

}  // namespace rangecal
