#pragma once
// The network's covariance (docs/optimisation.md "Network bundle — covariance"). With the whitened
// Jacobian split into camera columns (c) and point columns (p), the normal matrix is
//   N = [ U   W ]      U = Σ J_cᵀJ_c + camera priors,   W = Σ J_cᵀJ_p,
//       [ Wᵀ  V ]      V = blockdiag(V_k),  V_k = Σ J_pᵀJ_p + Σ_prior,k⁻¹,
// and the cameras' marginal covariance is the inverse of the Schur complement (Triggs et al. 2000
// §6.1)
//   S = U − Σ_k W_k·V_k⁻¹·W_kᵀ,      Σ_cc = S⁻¹,
// which keeps every correlation between cameras that the shared epochs create. Each point's
// covariance follows as Σ_kk = V_k⁻¹ + V_k⁻¹·W_kᵀ·Σ_cc·W_k·V_k⁻¹; a single-view point
// (network_parameters.hpp) has Σ − K·J_X·Σ + K·J_θ·Σ_cc·J_θᵀ·Kᵀ, K = Σ·J_Xᵀ·C⁻¹. S is inverted after Jacobi
// scaling, with the per-camera bundle's rank tests (optim/bundle/bundle_covariance.hpp). Under a
// correlated PPK error model the Gauss–Markov states are eliminated after the points
// (gauss_markov_elimination.hpp), and a chained point's covariance takes their share:
//   Σ_kk = V⁻¹ + V⁻¹·[(Wᵀ − P·Z_j)·Σ_cc·(Wᵀ − P·Z_j)ᵀ + P·(G⁻¹)_jj·P]·V⁻¹.
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "optim/network/gauss_markov_elimination.hpp"
#include "optim/network/network_parameters.hpp"

namespace rangecal {

/// A camera's free columns against a point's three (n_free × 3; fixed capacity, no heap).
using CameraPointBlock = Eigen::Matrix<double, Eigen::Dynamic, 3, 0, kBundleParameterCount, 3>;

/// A camera's free columns of a gradient (fixed capacity, no heap).
using CameraGradient = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kBundleParameterCount, 1>;

/// One point's share of the normal equations.
struct PointLinearisation {
  Eigen::Matrix3d V = Eigen::Matrix3d::Zero();  ///< V_k (m⁻²)
  /// The prior's information L⁻ᵀL⁻¹ when it is a fix in the Gauss–Markov chain (it then couples the
  /// point with its GM state: gauss_markov_elimination.hpp); zero otherwise.
  Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
  /// W_k per observing camera: (camera index, J_cᵀJ_p over that camera's used observations, n_free × 3).
  std::vector<std::pair<std::size_t, CameraPointBlock>> W;
  int cameras = 0;  ///< cameras with a used observation of the point
  /// The gradient Jᵀr of the point's residuals: on its block, on its Gauss–Markov state (chained
  /// fix), and per observing camera (its free columns), as W lists the cameras.
  Eigen::Vector3d grad_point = Eigen::Vector3d::Zero();
  Eigen::Vector3d grad_state = Eigen::Vector3d::Zero();
  std::vector<std::pair<std::size_t, CameraGradient>> grad_camera;
};

/// V_k and W_k of point k at `blocks` over the selection; when `U` is given, the observations'
/// J_cᵀJ_c are added to it (joint columns); `chi2`/`rows` accumulate the whitened residuals.
/// Throws rangecal::Error (calibration) when an observation cannot be projected.
PointLinearisation linearise_point(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                                   const NetworkSelection& selection, std::size_t k, Eigen::MatrixXd* U,
                                   double* chi2, int* rows);

/// A chained fix's coupling with its Gauss–Markov state `state` once its point is eliminated
/// (gauss_markov_elimination.hpp): G_jj += P − P·V⁻¹·P and B_j −= P·V⁻¹·Wᵀ, with `P` the fix's white
/// information and `Vinv` the point's V⁻¹ (fix included). Returns P·V⁻¹.
Eigen::Matrix3d couple_fix_to_state(const NetworkLayout& layout, std::size_t state, const Eigen::Matrix3d& P,
                                    const Eigen::Matrix3d& Vinv, const PointLinearisation& lin,
                                    GaussMarkovSystem* gm);

/// The camera priors' information into `U` (joint columns), their χ² and residual count, and with
/// `gradient` their share of Jᵀr (principal point, centre: as the per-camera bundle's priors).
void add_camera_priors(const NetworkLayout& layout, const NetworkParameterBlocks& blocks, Eigen::MatrixXd* U,
                       double* chi2, int* rows, Eigen::VectorXd* gradient = nullptr);

struct NetworkCovariance {
  Eigen::MatrixXd S;                       ///< reduced camera system (joint columns)
  Eigen::MatrixXd joint;                   ///< S⁻¹, a-priori; empty when rank-deficient
  std::vector<Eigen::Matrix3d> point_cov;  ///< per point (zero for points not used)
  /// Per point: the adjusted position — its block, or for a single-view point the posterior
  /// X̄ − Σ·J_Xᵀ·C⁻¹·e given the camera (e its pixel residual at X̄).
  std::vector<Eigen::Vector3d> point_enu;
  /// Per point in the Gauss–Markov chain, its state's estimate (ENU m; zero for the others).
  std::vector<Eigen::Vector3d> point_gm;
  double chi2 = 0;
  int residuals = 0;
  int parameters = 0;
  bool rank_deficient = false;
  std::vector<std::string> warnings;
  std::vector<Eigen::Index> named;  ///< the joint columns the warnings name (rank_tested_inverse)
};

/// One Gauss–Newton step of the whole network at `blocks` for the selection (plain least squares):
/// the same normal equations as the covariance's, with their gradient carried through the same
/// eliminations (points, then Gauss–Markov states, then the cameras' dense system). Writes the
/// step into `step` (cameras packed as CameraBlock, points, states) and returns the χ² at `blocks`.
/// Throws rangecal::Error (calibration) when the cameras' system is not positive definite.
struct NetworkStep {
  std::vector<Eigen::VectorXd> cameras;  ///< per camera, its free parameters in order
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> states;
  /// The fall of χ² the linearised model predicts for the whole step, bᵀ·M⁻¹·b — by the Schur
  /// identity Σ b_Xᵀ·V⁻¹·b_X + b̃_gᵀ·G⁻¹·b̃_g + b̃_cᵀ·S⁻¹·b̃_c over the same eliminations.
  double predicted_decrease = 0;
};
double network_gauss_newton_step(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                                 const NetworkSelection& selection, NetworkStep* step);

/// The covariance at `blocks` (rotations re-based) for the selection. `scene_distance_m` and
/// `max_speed_mps` set the physical ranges of the rank test (parameter_range).
NetworkCovariance network_covariance(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                                     const NetworkSelection& selection, double scene_distance_m,
                                     double max_speed_mps, double rank_tolerance);

}  // namespace rangecal
