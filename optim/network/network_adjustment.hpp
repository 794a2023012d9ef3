#pragma once
// Network bundle adjustment (docs/optimisation.md "Network bundle"): every camera and the lamp
// track adjusted together — self-calibrating bundle adjustment with weighted control, as
// photogrammetric networks are adjusted (Triggs et al. 2000 §6 on the Schur complement; Granshaw
// 1980 on self-calibration). Parameters:
//   - each camera's free set (BundleOptions::free, clock offset included), its priors as in the
//     per-camera bundle (optim/bundle/bundle_adjustment.hpp);
//   - one 3-vector per point: each used lamp epoch under its PPK prior (full 3×3 covariance), each
//     control pole under its survey prior.
// Cost: Σ ρ(‖r_img‖²) over image residuals (in σ_px units) + Σ ‖L⁻¹(X_k − X̄_k)‖² over the priors in
// use + the camera priors. The gauge (datum: position, scale, orientation) is fixed by the priors
// alone. Ceres Levenberg–Marquardt with the point blocks eliminated first (DENSE_SCHUR: the
// reduced camera system is at most a few hundred parameters).
//
// Steps (network_adjustment.cpp): robust solve (Huber or Cauchy on image residuals and on the
// priors), PPK outliers (optim/network/network_outliers.hpp: epochs whose multi-ray position
// disagrees with their fix, whitened test; prior dropped), image outliers (the per-camera bundle's
// rule), with NetworkOptions::estimate_ppk_error the variance components (PPK model, each camera's
// image σ: optim/network/ppk_error_estimation.hpp), a plain least-squares solve without the
// outliers, then the joint covariance of all cameras (the Schur complement,
// optim/network/network_covariance.hpp) and each adjusted point's covariance. When a camera's
// estimated centroid σ is more than 1.5× off its stated σ, the steps run once more at the estimated
// σ, so that the outlier tests weigh each ray by what it is worth.
//
// A camera that shares no epoch with another is calibrated from its own epochs exactly as the
// per-camera bundle would: eliminating a point seen once under its prior gives the bundle's
// effective pixel covariance σ_px²·I + J_X·Σ_X·J_Xᵀ (Woodbury identity).
#include <vector>

#include "optim/network/network_observation.hpp"
#include "optim/network/network_options.hpp"
#include "optim/network/network_result.hpp"

namespace rangecal {

/// Adjusts the network. Throws rangecal::Error: calibration kind for non-finite input (naming
/// the observation or point), an observation of an unknown camera or point, a prior covariance
/// that is not positive definite, a camera with fewer residuals than free parameters, a point
/// behind a starting camera, or a failed solve; usage kind for an unknown free-parameter name.
NetworkResult network_adjust(const std::vector<NetworkCamera>& cameras,
                             const std::vector<NetworkPoint>& points,
                             const std::vector<NetworkObservation>& observations,
                             const NetworkOptions& options = {});

}  // namespace rangecal
