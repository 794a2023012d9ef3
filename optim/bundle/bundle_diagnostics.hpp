#pragma once
// The bundle's warnings (docs/optimisation.md: "warnings when a parameter is poorly determined (σ large or
// |correlation| > 0.99)"; thresholds in docs/optimisation.md). Warnings, not errors: the
// calibration may still serve the intersection, which depends on combinations of parameters that
// are often far better determined than each one alone.
#include <string>
#include <vector>

#include "optim/bundle/bundle_details.hpp"
#include "optim/bundle/calibration_warning.hpp"
#include "vision/camera/calibration_result.hpp"

namespace rangecal {

/// A clock offset whose 1σ moves the fastest lamp point by more than this (m) is poorly
/// determined: twice the PPK noise of one epoch.
inline constexpr double kClockWarningM = 0.02;
/// Above this |δ| (s) the first-order model X − v·δ misses ½·a·δ² (≈ 2 mm at 1.5 m/s² and 50 ms):
/// the stamps should be corrected and the mission re-aligned instead.
inline constexpr double kLargeClockOffsetS = 0.05;

/// Per free parameter of `cal` (its covariance over cal.parameters): σ beyond the parameter's rule
/// — f more than 1 % of f; u0, v0 more than 5 % of the image; sx more than 0.01; a distortion term
/// whose 1σ moves the image corner by more than 1 px; a rotation more than 1 mrad; a centre
/// coordinate more than 1 m; a clock offset moving the fastest lamp point (`max_speed_mps`) more
/// than kClockWarningM — then every pair with |ρ| > correlation_warning. Kinds poorly_determined
/// (the parameter) and correlated (the pair).
std::vector<CalibrationWarning> poorly_determined_warnings(const CalibrationResult& cal, double max_speed_mps,
                                                           double correlation_warning);

/// On the fit as a whole: a clock offset beyond kLargeClockOffsetS; a χ² beyond its 1 % quantile
/// (the noise model is too optimistic or the model misses something); no redundancy (dof = 0).
std::vector<CalibrationWarning> fit_warnings(const BundleDetails& details);

}  // namespace rangecal
