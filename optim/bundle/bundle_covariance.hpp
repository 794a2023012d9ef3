#pragma once
// The bundle's covariance (docs/optimisation.md "Covariance"): from the whitened Jacobian J of
// every used residual and prior at the solution (columns: the free parameters), N = JᵀJ and
// Σ = N⁻¹, computed on Jacobi-scaled columns after the two-scale rank test the network shares
// (optim/estimation/rank_tested_inverse.hpp, the ranges of vision/camera/camera_parameters.hpp's
// parameter_range): when it fails the covariance is left empty and a warning names the parameters.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "optim/bundle/bundle_observation.hpp"
#include "optim/bundle/bundle_options.hpp"
#include "optim/bundle/bundle_parameters.hpp"
#include "optim/estimation/rank_tested_inverse.hpp"

namespace rangecal {

/// The whitened residuals r and Jacobian J (free columns only, canonical order) of the used
/// observations, then the priors in use, at `blocks` (whose rotation is re-based: w = 0).
struct WhitenedSystem {
  Eigen::MatrixXd J;
  Eigen::VectorXd r;
};
WhitenedSystem whitened_system(const BundleParameterBlocks& blocks, const Camera& base,
                               const std::vector<BundleObservation>& observations,
                               const std::vector<char>& used, const std::vector<Eigen::Matrix2d>& W,
                               const BundleSetup& setup, const BundleOptions& options);

/// The scene distance of the rank test: the camera centre's distance from the mean of every world
/// point (m, at least 1).
double bundle_scene_distance(const Camera& cam, const std::vector<BundleObservation>& observations);
/// The fastest lamp point (m/s): scales the clock offset in the rank test and its warning.
double bundle_max_speed(const std::vector<BundleObservation>& observations);

/// Σ = (JᵀJ)⁻¹ for the free parameters `free` of `cam`, with the rank tests above. `scene_distance_m`
/// and `max_speed_mps` set the physical ranges of the pose and the clock offset.
RankTestedInverse estimate_covariance(const Eigen::MatrixXd& J, const std::vector<CameraParameter>& free,
                                      const Camera& cam, double scene_distance_m, double max_speed_mps,
                                      double rank_tolerance);

}  // namespace rangecal
