#pragma once
// What the bundle refuses before solving (docs/accuracy_analysis.md, Quality bars "bad input": degenerate
// geometry is a clear error naming the cause, exit 4): non-finite observations, fewer equations than
// unknowns, points all on one line (a single vertical ascent leaves the rotation about it free), points
// behind the starting camera, a free clock offset with no lamp velocity, priors without a finite value or σ.
#include <vector>

#include "optim/bundle/bundle_observation.hpp"
#include "optim/bundle/bundle_options.hpp"
#include "optim/bundle/bundle_parameters.hpp"

namespace rangecal {

/// Throws rangecal::Error (calibration) naming the observation and field, or the cause.
void check_bundle_input(const Camera& initial, const std::vector<BundleObservation>& observations,
                        const BundleSetup& setup, const BundleOptions& options);

}  // namespace rangecal
