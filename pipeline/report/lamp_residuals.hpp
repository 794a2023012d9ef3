#pragma once
// The lamp pairs of one camera as the report plots them: observed pixel, reprojection through the
// calibrated camera, observed − reprojected, whether the calibration used the pair, and the σ the
// noise model expects of that residual (docs/accuracy_analysis.md "Noise model"):
//   C_i = σ_px²·I + J_X·Σ_X·J_Xᵀ,  J_X = ∂pixel/∂X,  Σ_X = S·diag(sdE², sdN², sdU²)·S + diag(σ_g²)
// (kDefaultWorldSigmaM where correspondences.csv carries no sd), so σu = √C_i(0,0), σv = √C_i(1,1).
// S and σ_g are those of the PPK error model the calibration weighed the fixes by
// (gnss/track/ppk_error_model.hpp: a fix's error is white S·Σ_pos·S plus a Gauss–Markov part of
// stationary variance σ_g²): the residual against the fix carries both parts. Without a model,
// S = I and σ_g = 0.
#include <Eigen/Core>
#include <limits>
#include <vector>

#include "gnss/track/ppk_error_model.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/residuals_csv.hpp"
#include "vision/camera/calibration_result.hpp"

namespace rangecal {

struct LampResidual {
  UtcTime utc;
  Eigen::Vector2d observed = Eigen::Vector2d::Zero();  ///< px
  bool projected = false;                              ///< the world point projects (calibrated camera)
  Eigen::Vector2d reprojected = Eigen::Vector2d::Zero();
  Eigen::Vector2d residual = Eigen::Vector2d::Zero();  ///< observed − reprojected (px)
  bool used = true;                                    ///< residuals.csv's `used` (all when absent)
  Eigen::Vector2d sigma_px =                           ///< noise model's σu, σv (px); NaN uncalibrated
      Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Matrix2d cov_px = Eigen::Matrix2d::Zero();  ///< the noise model's C_i (px²), projected pairs
  Eigen::Matrix<double, 2, 3> world_jacobian =       ///< J_X (px/m), projected pairs
      Eigen::Matrix<double, 2, 3>::Zero();
  /// J_X·v: how fast the lamp moves in the image (px/s); NaN without the fix's velocity.
  Eigen::Vector2d image_velocity_px_s = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
};

/// One entry per pair, in file order. `calibration` may be null (then nothing projects);
/// `residuals` (residuals.csv) may be null (then every pair counts as used); its lamp rows follow
/// the pairs one to one. The lamp is reprojected where it was at the true exposure (position −
/// velocity × clock offset, optim/bundle/bundle_adjustment.hpp). `pixel_sigma_px`: the centroid σ
/// the calibration assumed (kDefaultPixelSigmaPx). `ppk_model`: the PPK error model the calibration
/// weighed the fixes by (null: white, S = I).
std::vector<LampResidual> lamp_residuals(const std::vector<Correspondence>& pairs,
                                         const CalibrationResult* calibration,
                                         const std::vector<ResidualRow>* residuals, double pixel_sigma_px,
                                         const PpkErrorModel* ppk_model = nullptr);

/// Observed RMS of |residual| over used, projected pairs, and the RMS the noise model expects:
/// √(mean trace C_i · (2n − p)/(2n)), p the number of estimated parameters (the fit absorbs p of
/// the 2n degrees of freedom).
struct ResidualConsistency {
  int n = 0;
  double rms_px = std::numeric_limits<double>::quiet_NaN();
  double expected_rms_px = std::numeric_limits<double>::quiet_NaN();
};
ResidualConsistency residual_consistency(const std::vector<LampResidual>& r, int n_parameters);

/// A camera clock offset δ left in the residuals: the lamp was where it is δ later, so each residual
/// is −J_X·v·δ (the reprojection of bundle_adjustment.hpp's clock model, to first order). The
/// least-squares δ over used, projected pairs with a velocity, δ̂ = −Σ g_iᵀ r_i / Σ |g_i|² with
/// g_i = J_X·v_i, and its σ under the noise model — the white C_i and, under a correlated PPK model,
/// the Gauss–Markov part shared between pairs, E[g_j g_iᵀ] = σ_g²·exp(−|t_i − t_j|/τ) per axis
/// (docs/optimisation.md "Correlated PPK errors"; the sum over pairs in one pass by the model's AR(1)
/// recursion on sorted times). A slow PPK error
/// that happens to follow the lamp's speed therefore does not pass for a clock offset.
struct ClockOffsetSignature {
  int n = 0;  ///< pairs with a velocity
  double offset_s = std::numeric_limits<double>::quiet_NaN();
  double sigma_s = std::numeric_limits<double>::quiet_NaN();
};
ClockOffsetSignature clock_offset_signature(const std::vector<LampResidual>& r,
                                            const PpkErrorModel* ppk_model);

}  // namespace rangecal
