#pragma once
// The lamp pairs of one camera as the report plots them: observed pixel, reprojection through the
// calibrated camera, observed − reprojected, whether the calibration used the pair, and the σ the
// noise model expects of that residual (docs/accuracy_analysis.md "Noise model"):
//   C_i = σ_px²·I + J_X·Σ_X·J_Xᵀ,  J_X = ∂pixel/∂X,  Σ_X = diag(sdE², sdN², sdU²)
// (kDefaultWorldSigmaM where correspondences.csv carries no sd), so σu = √C_i(0,0), σv = √C_i(1,1).
#include <Eigen/Core>
#include <limits>
#include <vector>

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
};

/// One entry per pair, in file order. `calibration` may be null (then nothing projects);
/// `residuals` (residuals.csv) may be null (then every pair counts as used); its lamp rows follow
/// the pairs one to one. The lamp is reprojected where it was at the true exposure (position −
/// velocity × clock offset, optim/bundle/bundle_adjustment.hpp). `pixel_sigma_px`: the centroid σ
/// the calibration assumed (kDefaultPixelSigmaPx).
std::vector<LampResidual> lamp_residuals(const std::vector<Correspondence>& pairs,
                                         const CalibrationResult* calibration,
                                         const std::vector<ResidualRow>* residuals, double pixel_sigma_px);

/// Observed RMS of |residual| over used, projected pairs, and the RMS the noise model expects:
/// √(mean trace C_i · (2n − p)/(2n)), p the number of estimated parameters (the fit absorbs p of
/// the 2n degrees of freedom).
struct ResidualConsistency {
  int n = 0;
  double rms_px = std::numeric_limits<double>::quiet_NaN();
  double expected_rms_px = std::numeric_limits<double>::quiet_NaN();
};
ResidualConsistency residual_consistency(const std::vector<LampResidual>& r, int n_parameters);

}  // namespace rangecal
