#pragma once
// The network's parameters as Ceres sees them: each camera's four blocks (the per-camera bundle's,
// optim/bundle/bundle_parameters.hpp, with the same free sets and priors) and one 3-vector per
// point. Which observations and priors take part in a solve is kept beside them.
#include <array>
#include <vector>

#include "optim/bundle/bundle_parameters.hpp"
#include "optim/network/network_adjustment.hpp"

namespace rangecal {

/// A point's block: X_k (ENU m), eliminated first by the Schur solver.
inline constexpr int kPointBlockSize = 3;

struct NetworkParameterBlocks {
  std::vector<BundleParameterBlocks> cameras;
  std::vector<std::array<double, kPointBlockSize>> points;  ///< ENU m
};

/// The problem's fixed layout: per camera its set-up, starting camera, free parameters and the
/// offset of its columns in the joint covariance; per point its observations and prior whitening.
struct NetworkLayout {
  const std::vector<NetworkCamera>* cameras = nullptr;
  const std::vector<NetworkPoint>* points = nullptr;
  const std::vector<NetworkObservation>* observations = nullptr;
  std::vector<BundleSetup> setups;
  std::vector<Camera> starts;
  std::vector<std::vector<CameraParameter>> free;
  std::vector<int> offset;  ///< first joint column of each camera
  int n_camera_parameters = 0;
  std::vector<std::vector<std::size_t>> by_point;
  std::vector<Eigen::Matrix3d> prior_whiten;  ///< L⁻¹ per point
  /// Multiplies every observation's σ_px: 1 for the network itself, 1/kDatumFloorImageFactor for
  /// its datum floor (network_adjustment.hpp).
  double pixel_sigma_scale = 1;

  /// σ_px of observation i: its own, else its camera's default, times pixel_sigma_scale.
  double pixel_sigma(std::size_t i) const;
};

NetworkLayout make_network_layout(const std::vector<NetworkCamera>& cameras,
                                  const std::vector<NetworkPoint>& points,
                                  const std::vector<NetworkObservation>& observations);

/// The solve's start: each camera at its starting camera and initial clock offset, each point at
/// its prior.
NetworkParameterBlocks starting_blocks(const NetworkLayout& layout);

/// What enters a solve: observations (image residuals) and point priors; and which points are
/// eliminated analytically. A lamp epoch seen by one camera under its prior has no image
/// redundancy of its own: eliminating its point gives exactly the per-camera bundle's residual
/// W·(project(X̄ + offset − v·δ) − uv) with W = L⁻¹, L·Lᵀ = σ_px²·I + J_X·Σ_X·J_Xᵀ (Woodbury; optim/bundle/
/// whitening.hpp), so such an observation enters as that residual with W fixed for the solve (the
/// bundle's iterated effective variance) and no point block — and a camera alone is the bundle.
struct NetworkSelection {
  std::vector<char> observation;           ///< per observation: used
  std::vector<char> prior;                 ///< per point: its prior used
  std::vector<char> single_view;           ///< per point: eliminated analytically (see above)
  std::vector<Eigen::Matrix2d> whitening;  ///< per observation of a single-view point: W (px⁻¹)
};

/// Marks the single-view points of `selection` (prior used, exactly one used observation) and
/// computes their observations' W at the cameras of `blocks`.
void refresh_single_view(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                         NetworkSelection* selection);

}  // namespace rangecal
