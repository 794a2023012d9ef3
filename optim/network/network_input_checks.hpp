#pragma once
// What the network refuses before solving (as the per-camera bundle, optim/bundle/bundle_input_checks.hpp,
// applied to each camera's view of the points at their priors): observations of unknown cameras
// or points, non-finite values, prior covariances that are not positive definite, and each
// camera's own degenerate cases (too few points, one line, behind the camera, clock offset free
// without velocity).
#include <vector>

#include "optim/bundle/bundle_observation.hpp"
#include "optim/network/network_observation.hpp"
#include "optim/network/network_options.hpp"

namespace rangecal {

/// Each camera's observations as the per-camera bundle would see them: the point's prior moved to
/// the frame time (prior + offset) with the prior covariance, the pixel, its σ and the velocity.
std::vector<BundleObservation> camera_bundle_observations(
    std::size_t camera, const std::vector<NetworkPoint>& points,
    const std::vector<NetworkObservation>& observations);

/// Throws rangecal::Error (calibration) naming the observation, point or camera and the cause.
void check_network_input(const std::vector<NetworkCamera>& cameras, const std::vector<NetworkPoint>& points,
                         const std::vector<NetworkObservation>& observations);

}  // namespace rangecal
