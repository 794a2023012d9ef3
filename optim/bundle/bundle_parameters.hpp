#pragma once
// The bundle's parameters as Ceres sees them (four blocks, optim/bundle/reprojection_cost.hpp)
// and which of them are free. The rotation is a perturbation w about R0: R = exp([w]×)·R0,
// re-based to w = 0 between solves so the covariance is about the final R.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "optim/bundle/bundle_options.hpp"
#include "optim/bundle/reprojection_cost.hpp"
#include "vision/camera/camera_model.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal {

struct BundleParameterBlocks {
  double intr[kIntrinsicsBlockSize];
  double dist[kDistortionBlockSize];
  double pose[kPoseBlockSize];
  double clock[kClockBlockSize] = {0};
  Eigen::Matrix3d R0;

  /// The blocks of `c` (w = 0, R0 = c.R) with clock offset `clock_offset_s` (s).
  static BundleParameterBlocks from_camera(const Camera& c, double clock_offset_s = 0);
  /// `base` (id, sensor) with the blocks' parameters.
  Camera to_camera(const Camera& base) const;
  /// R0 ← exp([w]×)·R0, w ← 0 (the camera is unchanged).
  void rebase_rotation(const Camera& base);
  double* block(int b) { return b == 0 ? intr : b == 1 ? dist : b == 2 ? pose : clock; }
};

inline constexpr std::array<int, 4> kBundleBlockSizes = {kIntrinsicsBlockSize, kDistortionBlockSize,
                                                         kPoseBlockSize, kClockBlockSize};

/// The free parameters (canonical index → free) and the priors in use.
struct BundleSetup {
  std::array<bool, kBundleParameterCount> free{};
  int n_free = 0;
  bool principal_point_prior = false;
  bool center_prior = false;
  bool is_free(CameraParameter p) const { return free[static_cast<std::size_t>(index_of(p))]; }
  /// The free parameters in canonical order.
  std::vector<CameraParameter> free_parameters() const;
};

/// The free parameters of `options` (calibrate.free expanded) and the priors in use: the principal
/// point prior when u0 or v0 is free, the centre prior when a centre coordinate is (the per-camera
/// bundle's and every network camera's set-up).
BundleSetup bundle_setup(const BundleOptions& options);

/// The starting camera: `initial` with a fixed principal point at its prior when one is given
/// (docs/optimisation.md, "Bundle adjustment").
Camera bundle_starting_camera(const Camera& initial, const BundleSetup& setup, const BundleOptions& options);

}  // namespace rangecal
