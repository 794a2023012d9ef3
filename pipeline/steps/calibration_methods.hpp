#pragma once
// The calibrate stage's methods (docs/optimisation.md) behind one function: the same problem in, the same
// CalibrationResult out, so `compare` can run several on the same data (seed 002 Table 1).
//   tsai        Tsai two-step (vision/calibration/tsai.hpp): R, Tx, Ty, sx linearly, then f, Tz, k1.
//   tsai_sassa  seed 002's method: Tsai step 1, then f, Tz, k1 by SA-sparrow search, LM polish
//               (optim/methods/tsai_sassa.hpp).
//   dlt_lmqn    seed 000: DLT with RANSAC, linear distortion, LM / quasi-Newton hybrid
//               (optim/methods/dlt_lmqn.hpp).
//   bundle      Ceres LM over the free parameters from the Tsai start (DLT if Tsai fails or needed its
//               fallbacks, vision/calibration/tsai.hpp), priors,
//               robust loss, outliers, covariance and warnings (optim/bundle/bundle_adjustment.hpp).
// Parameters not free stay at: u0, v0 = the prior (else the image centre), sx = 1, distortion 0
// (hold_fixed_intrinsics, vision/camera/camera_parameters.hpp; docs/optimisation.md).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "optim/bundle/bundle_adjustment.hpp"
#include "optim/bundle/calibration_warning.hpp"
#include "pipeline/mission/calibration_method_names.hpp"
#include "pipeline/steps/calibration_problem.hpp"
#include "vision/camera/calibration_result.hpp"

namespace rangecal {

/// A method's result with its warnings typed (optim/bundle/calibration_warning.hpp):
/// result.warnings are their texts, in the same order.
struct CalibrationRun {
  CalibrationResult result;
  std::vector<CalibrationWarning> warnings;
};

/// Runs `method` on `problem`. The result's reprojection statistics cover the observations the
/// method used; `rejected` lists the others; `details` what the method did
/// (pipeline/io/method_details_json.hpp). Throws rangecal::Error: usage for an unknown method
/// (or `planar`, which needs views of a planar target, not a lamp track); calibration when the
/// geometry is degenerate or the method fails.
CalibrationRun run_calibration_method(const std::string& method, const CalibrationProblem& problem);
/// run_calibration_method's result alone.
CalibrationResult calibrate_camera(const std::string& method, const CalibrationProblem& problem);

/// Per-observation reprojection residual (projected − observed, px) of `cam`, each world point
/// moved to where the lamp stood at the true exposure time for a camera clock offset (s,
/// observed_world_point); NaN when a point cannot be projected.
std::vector<Eigen::Vector2d> reprojection_residuals(const Camera& cam,
                                                    const std::vector<BundleObservation>& obs,
                                                    double clock_offset_s = 0);
/// rms/mean/max of |residual| over the observations not in `rejected`
/// (optim/estimation/reprojection_stats.hpp), n_rejected the size of `rejected`.
ReprojectionStats reprojection_stats(const std::vector<Eigen::Vector2d>& residuals,
                                     const std::vector<std::size_t>& rejected);

}  // namespace rangecal
