#pragma once
// A compared method's σ under the PPK error model the network estimated (docs/optimisation.md "σ under
// correlated PPK errors"). Tsai, its SA-sparrow variant and DLT-LMQN give no covariance (Tsai) or
// N⁻¹ of their own white weighting (DLT-LMQN); under a model with a Gauss–Markov part the fixes'
// slow error moves every method's camera far beyond that. Their σ become the bundle's at the
// method's own solution: the whitened system of method `bundle` (its options, free set and priors)
// at the method's camera, over the observations it did not reject, and the sandwich N⁻¹·M·N⁻¹ under
// the model (optim/bundle/correlated_ppk_covariance.hpp bundle_covariance_under). That is the
// covariance of the white-weighted estimator at that camera; the method's estimate stays its own and
// the method is not run again.
#include "gnss/track/ppk_error_model.hpp"
#include "pipeline/steps/calibration_problem.hpp"
#include "vision/camera/calibration_result.hpp"

namespace rangecal {

/// `result` (a compared method's, solved on `problem`) with parameters, covariance and centre
/// covariance replaced by the bundle's sandwich under `model` at its camera, and its details
/// recording the model (`ppk_error_model`, `covariance`). A method that holds the clock offset at 0
/// (every one but the bundle) gets no clock-offset row. When the system is rank-deficient the
/// covariance is left empty, with a warning.
void restate_covariance_under(const PpkErrorModel& model, const CalibrationProblem& problem,
                              CalibrationResult* result);

}  // namespace rangecal
