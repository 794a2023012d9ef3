#pragma once
// The Gauss–Markov states' part of the network's covariance (docs/optimisation.md "Correlated PPK
// errors"). Once the points are eliminated (network_covariance.hpp), the reduced normal equations over
// the cameras (c) and the GM states (g, one 3-vector per chained epoch, in time order) are
//   [ S_cc  Bᵀ ]      G block tridiagonal: each epoch's fix couples g_j with its point
//   [ B     G  ]      (P − P·V⁻¹·P, P the white prior's information), the AR(1) chain couples g_j
//                     with g_{j±1} (gnss/track/ppk_error_model.hpp); B = S_gc = −P·V⁻¹·Wᵀ per epoch,
// and the cameras' Schur complement is S = S_cc − Bᵀ·G⁻¹·B. G = L·Lᵀ is factored block by block
// (L block lower bidiagonal, O(epochs)); Y = L⁻¹·B gives S −= Yᵀ·Y, and Z = L⁻ᵀ·Y = G⁻¹·B with the
// diagonal blocks of G⁻¹ (the backward recursion M_jj = L_jj⁻ᵀ·L_jj⁻¹ + C_jᵀ·M_{j+1,j+1}·C_j,
// C_j = L_{j+1,j}·L_jj⁻¹, as a Rauch–Tung–Striebel smoother runs) give the states' covariance
//   Σ_gg = G⁻¹ + Z·Σ_cc·Zᵀ,   Σ_gc = −Z·Σ_cc.
#include <Eigen/Core>
#include <vector>

namespace rangecal {

struct GaussMarkovSystem {
  std::vector<Eigen::Matrix3d> diagonal;  ///< G_jj (m⁻²)
  std::vector<Eigen::Vector3d> below;     ///< G_{j,j−1}, diagonal (below[0] unused)
  Eigen::MatrixXd B;                      ///< S_gc: 3·states × camera columns; becomes Z = G⁻¹·B
  Eigen::VectorXd gradient;               ///< b_g, the states' reduced gradient (a Gauss–Newton step's)
};

/// G's block Cholesky factor L (G = L·Lᵀ, L block lower bidiagonal): L_jj lower triangular, its
/// inverse (the substitutions multiply by it: faster than a triangular solve on 3 rows), and
/// L_{j,j−1}.
struct GaussMarkovFactor {
  std::vector<Eigen::Matrix3d> diagonal, diagonal_inverse, below;
};

/// Factors G (system->diagonal, system->below). Throws rangecal::Error (calibration) when G is not
/// positive definite.
GaussMarkovFactor factor_gauss_markov(const GaussMarkovSystem& system);

/// rhs ← G⁻¹·rhs (3·states rows, any columns), by the factor's forward and backward
/// substitutions: O(states).
void solve_gauss_markov(const GaussMarkovFactor& factor, Eigen::MatrixXd* rhs);

/// The blocks (G⁻¹)_{j,j−1} (index j; the first unused) from the factor and the diagonal blocks of
/// G⁻¹ that eliminate_gauss_markov returns: LᵀG⁻¹ = L⁻¹ is lower triangular, so
/// (G⁻¹)_{j,j−1} = −(G⁻¹)_jj·L_{j,j−1}·L_{j−1,j−1}⁻¹.
std::vector<Eigen::Matrix3d> gauss_markov_inverse_below(const GaussMarkovFactor& factor,
                                                        const std::vector<Eigen::Matrix3d>& inverse_diagonal);

/// Eliminates the states: S −= Bᵀ·G⁻¹·B (both triangles of S kept), system->B replaced by Z = G⁻¹·B.
/// With `state_rhs` (b_g) and `camera_rhs` (b_c) for a Gauss–Newton step: b_c −= Bᵀ·G⁻¹·b_g and
/// b_g replaced by G⁻¹·b_g. With `log_det`, log|G| (from the factor's diagonal, for the restricted
/// likelihood: ppk_error_estimation.hpp). Returns the diagonal blocks of G⁻¹. Throws rangecal::Error
/// (calibration) when G is not positive definite. With `factor`, G's factor is kept there.
std::vector<Eigen::Matrix3d> eliminate_gauss_markov(GaussMarkovSystem* system, Eigen::MatrixXd* S,
                                                    Eigen::VectorXd* state_rhs = nullptr,
                                                    Eigen::VectorXd* camera_rhs = nullptr,
                                                    double* log_det = nullptr,
                                                    GaussMarkovFactor* factor = nullptr);

}  // namespace rangecal
