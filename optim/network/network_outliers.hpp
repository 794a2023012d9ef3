#pragma once
// The network's outlier rules (docs/optimisation.md "Network bundle — outliers").
//
// PPK outliers. At the robust solution, an epoch seen by ≥ 2 cameras has a position fixed by the
// rays alone to about a millimetre, so its fix can be tested against it. With r = X̂_k − X̄_k and
// its covariance Σ_r = Σ_prior − V_k⁻¹ (least-squares residual of a prior; V_k the point's
// information with the cameras held, Förstner's redundancy in 3-D), the whitened statistic
//   d² = rᵀ·Σ_r⁺·r    (pseudo-inverse over the eigenvalues above 1e-6 of the largest: m ≤ 3 of them)
// is χ²_m under a correct fix; d² above the χ²_m quantile of tail probability α flags the epoch and
// its prior is dropped in the final solve. An epoch seen by one camera cannot separate a bad fix
// from a bad pixel: the image rule below covers it, as in the per-camera bundle.
//
// Image outliers: the per-camera bundle's rule, per camera, on the bundle's own statistic —
// ‖C_i^(−1/2)·e_i‖, e_i the pixel residual of the camera at the point's prior position (at the
// adjusted point, with its covariance from the rays, when the prior was dropped), C_i = σ_px²·I +
// J_X·Σ·J_Xᵀ — flagged above outlier_threshold·max(1, s), s the robust scale of the camera's used
// observations (optim/estimation/robust_scale.hpp). With one camera this is exactly the per-camera
// bundle's rule.
#include <Eigen/Core>
#include <vector>

#include "optim/network/network_parameters.hpp"
#include "optim/network/network_result.hpp"

namespace rangecal {

/// The χ²_m quantile (m = 1, 2, 3) of upper-tail probability `alpha` (0 < α < 1), by bisection on
/// the closed-form survival functions.
double chi2_upper_quantile(int m, double alpha);

/// Tests every lamp point whose prior is in `selection` and that ≥ 2 cameras see (used
/// observations); fills d², m and the flag of `points` and drops the flagged priors from
/// `selection`. Returns the flagged point indices.
std::vector<std::size_t> flag_ppk_outliers(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                                           double alpha, NetworkSelection* selection,
                                           std::vector<NetworkPointResult>* points);

/// Per observation: pixel residual (projected at the reference point above − observed, px; with one
/// camera the per-camera bundle's residual), whitened norm
/// of the bundle's statistic, flag. Threshold per camera.
struct ImageOutlierTest {
  std::vector<Eigen::Vector2d> residual_px;
  std::vector<double> whitened_norm;
  std::vector<bool> outlier;
  std::vector<double> threshold;  ///< per camera (σ units)
};

ImageOutlierTest test_image_observations(const NetworkLayout& layout, const NetworkParameterBlocks& blocks,
                                         const NetworkSelection& selection, double outlier_threshold);

}  // namespace rangecal
