#pragma once
// One camera as one Ceres parameter block: its free parameters, packed in canonical order
// (vision/camera/camera_parameters.hpp). The per-camera bundle gives each camera four blocks
// with subset manifolds; in the network the Schur eliminator then handles four small blocks per
// camera at every point, and pays for each pair. One block per camera and cost functions that
// write only its free columns (network_cost_functions.hpp) keep that work to one dense block per
// camera pair (docs/performance.md, network bundle).
#include <Eigen/Core>
#include <array>

#include "optim/bundle/bundle_parameters.hpp"
#include "optim/bundle/projection_jacobian.hpp"

namespace rangecal {

struct CameraBlock {
  std::array<double, kBundleParameterCount> all{};     ///< every parameter, canonical order; the eval point
  std::array<int, kBundleParameterCount> index{};      ///< canonical index of packed entry j
  std::array<double, kBundleParameterCount> values{};  ///< the Ceres block: the free parameters
  int size = 0;                                        ///< number of free parameters
  Eigen::Matrix3d R0 = Eigen::Matrix3d::Identity();    ///< rotation the pose's w perturbs
  double dx_mm = 0, dy_mm = 0;                         ///< pixel pitch

  /// The block of camera `blocks` with free set `setup`; pixel pitch of `base`.
  static CameraBlock pack(const BundleSetup& setup, const BundleParameterBlocks& blocks, const Camera& base);
  /// The parameters with packed values `x` (size entries; null: the held values) in place of the free ones.
  void expand(const double* x, double* out) const;
  /// Writes the block's values back into `blocks` (R0 unchanged).
  void unpack(BundleParameterBlocks* blocks) const;

  /// The point Ceres evaluates at, per camera rather than per observation: prepare_evaluation puts
  /// `values` into `all` and forms the rotation R(w)·R0 with its J_l. The network's Ceres problem
  /// calls it before each evaluation (network_ceres_problem.hpp).
  PoseRotation rotation;
  void prepare_evaluation();
};

}  // namespace rangecal
