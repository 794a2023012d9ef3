#pragma once
// The network's parameters as Ceres sees them: each camera's four blocks (the per-camera bundle's,
// optim/bundle/bundle_parameters.hpp, with the same free sets and priors) and one 3-vector per
// point. Which observations and priors take part in a solve is kept beside them.
#include <array>
#include <vector>

#include "gnss/track/ppk_error_model.hpp"
#include "optim/bundle/bundle_parameters.hpp"
#include "optim/network/network_observation.hpp"
#include "optim/network/network_options.hpp"

namespace rangecal {

/// A point's block: X_k (ENU m), eliminated first by the Schur solver.
inline constexpr int kPointBlockSize = 3;

struct NetworkParameterBlocks {
  std::vector<BundleParameterBlocks> cameras;
  std::vector<std::array<double, kPointBlockSize>> points;  ///< ENU m
  /// The PPK error's Gauss–Markov states g (ENU m), one per state of NetworkLayout::gm_chain.
  std::vector<std::array<double, 3>> gm;
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
  /// L⁻¹ per point, L·Lᵀ its prior's covariance: the survey's for a pole; the white part
  /// S·Σ_pos·S of the error model for a PPK epoch (gnss/track/ppk_error_model.hpp).
  std::vector<Eigen::Matrix3d> prior_whiten;
  /// Per point, the whole covariance of its prior under the error model (white part + σ_g²): what
  /// the outlier tests weigh a fix by alone.
  std::vector<Eigen::Matrix3d> prior_total_cov;
  PpkErrorModel ppk;
  /// The Gauss–Markov chain (empty unless ppk.correlated()): its states' points in time order, and
  /// per point its state (−1: none, the point's prior is white).
  std::vector<std::size_t> gm_chain;
  std::vector<int> gm_state;
  /// Multiplies every observation's σ_px: 1 for the network itself, 1/kDatumFloorImageFactor for
  /// its datum floor (network_options.hpp).
  double pixel_sigma_scale = 1;

  /// σ_px of observation i: its own, else its camera's default, times pixel_sigma_scale.
  double pixel_sigma(std::size_t i) const;
};

NetworkLayout make_network_layout(const std::vector<NetworkCamera>& cameras,
                                  const std::vector<NetworkPoint>& points,
                                  const std::vector<NetworkObservation>& observations,
                                  const PpkErrorModel& ppk = {});

/// `layout` with each fix white under its whole covariance (prior_total_cov) and no chain: the
/// correlated model's white approximation, for the robust solve that separates outliers.
NetworkLayout white_approximation(const NetworkLayout& layout);

/// φ and the weights of chain state j's residual (gauss_markov_weight): of the first state when j = 0.
struct GaussMarkovStep {
  Eigen::Vector3d phi = Eigen::Vector3d::Zero();
  Eigen::Vector3d weight = Eigen::Vector3d::Zero();
};
GaussMarkovStep gauss_markov_step(const NetworkLayout& layout, std::size_t j);

/// The solve's start: each camera at its starting camera and initial clock offset, each point at
/// its prior, each Gauss–Markov state at 0.
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

/// Marks the single-view points of `selection` (prior used, exactly one used observation, not in
/// the Gauss–Markov chain: a chained fix is not independent of the others) and
/// computes their observations' W at the cameras of `blocks`.
void refresh_single_view(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                         NetworkSelection* selection);

}  // namespace rangecal
