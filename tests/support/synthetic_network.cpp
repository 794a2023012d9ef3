#include "support/synthetic_network.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>

#include "support/synthetic_camera.hpp"

namespace rangecal::test {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

SyntheticNetwork synthetic_network(int n_cameras, int n_epochs, std::uint64_t seed) {
  SyntheticNetwork n;
  const Vector3d aim(0, 0, 20);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N01;
  std::uniform_real_distribution<double> U(-1, 1);
  for (int c = 0; c < n_cameras; ++c) {
    const double a = 2 * M_PI * c / n_cameras + 0.3;
    const Camera t = range_camera_at("cam" + std::to_string(c + 1),
                                     aim + Vector3d(64 * std::cos(a), 64 * std::sin(a), -18.5), aim);
    n.truth.push_back(t);
    NetworkCamera nc;
    nc.initial = t;
    nc.initial.intr.f_mm *= 1.002;
    const Vector3d C = t.pose.center() + Vector3d(0.03, -0.02, 0.04);
    nc.initial.pose.R =
        Eigen::AngleAxisd(3e-4, Vector3d(1, -1, 0.5).normalized()).toRotationMatrix() * t.pose.R;
    nc.initial.pose.T = -nc.initial.pose.R * C;
    nc.options.free = {"f", "k1", "pose"};
    n.cameras.push_back(nc);
  }
  // A lamp climbing and sinking through the common field of view (±2.5 m across, ±2 m in height).
  for (int k = 0; k < n_epochs; ++k) {
    const Vector3d X = aim + Vector3d(2.5 * U(rng), 2.5 * U(rng), 2.0 * U(rng));
    NetworkPoint p;
    p.prior_cov = Matrix3d::Identity() * 1e-4;
    p.prior_enu = X + 0.01 * Vector3d(N01(rng), N01(rng), N01(rng));
    p.source = "epoch " + std::to_string(k);
    p.time_s = 0.2 * k;  // 5 Hz fixes: their place in a correlated error model's chain
    bool seen = false;
    for (int c = 0; c < n_cameras; ++c) {
      Vector2d uv;
      if (!project(n.truth[static_cast<std::size_t>(c)], X, &uv)) continue;
      if (uv.x() < 0 || uv.x() > 1280 || uv.y() < 0 || uv.y() > 800) continue;
      NetworkObservation o;
      o.camera = static_cast<std::size_t>(c);
      o.point = n.points.size();
      o.pixel = uv + 0.05 * Vector2d(N01(rng), N01(rng));
      o.pixel_sigma_px = 0.05;
      n.observations.push_back(o);
      seen = true;
    }
    if (seen) n.points.push_back(p);
  }
  return n;
}

void lay_out_network(NetworkScene* scene, std::optional<double> clock_s) {
  NetworkScene& n = *scene;
  n.layout = make_network_layout(n.data.cameras, n.data.points, n.data.observations);
  n.blocks = starting_blocks(n.layout);
  if (clock_s)
    for (BundleParameterBlocks& c : n.blocks.cameras) c.clock[0] = *clock_s;
  n.selection = {
      std::vector<char>(n.data.observations.size(), 1), std::vector<char>(n.data.points.size(), 1), {}, {}};
  refresh_single_view(n.layout, n.blocks, &n.selection);
}

}  // namespace rangecal::test
