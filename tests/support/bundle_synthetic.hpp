#pragma once
// Synthetic single-camera scenes for the optimiser tests (optim/): a seed-002-like narrow-field
// camera (1280×800, 20 µm pixels, 135 mm → 10.8° × 6.8° field of view, ~64 m from the points)
// and points spread over the image at depths 52–76 m, projected exactly by vision's camera model.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "vision/camera/camera_model.hpp"

namespace rangecal::test {

/// The seed-002-like truth camera: f 135 mm, 20 µm pixels, 1280×800, u0 v0 near the centre,
/// sx 1, k1 = k1_per_mm2, centre (0, 0, 1.5) looking ~64 m north-east and up.
Camera narrow_fov_camera(double k1_per_mm2 = 2e-5);

struct SyntheticPoints {
  std::vector<Eigen::Vector3d> world;  ///< ENU m
  std::vector<Eigen::Vector2d> pixel;  ///< exact projections (px)
};

/// n points at pixels uniform in the image (margin 20 px) and camera depths uniform in
/// [depth_min, depth_max] m, placed by the exact inverse of cam's model; fixed seed.
SyntheticPoints synthetic_points(const Camera& cam, int n, std::uint64_t seed, double depth_min = 52,
                                 double depth_max = 76);

}  // namespace rangecal::test
