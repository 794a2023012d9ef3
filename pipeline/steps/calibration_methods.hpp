#pragma once
// The calibrate stage's methods (SPEC §4.4) behind one function: the same problem in, the same
// CalibrationResult out, so `compare` can run several on the same data (seed 002 Table 1).
//   tsai        Tsai two-step (vision/calibration/tsai.hpp): R, Tx, Ty, sx linearly, then f, Tz, k1.
//   tsai_sassa  seed 002's method: Tsai step 1, then f, Tz, k1 by SA-sparrow search, LM polish.
//   dlt_lmqn    seed 000: normalised DLT with RANSAC → K, R, C; linear distortion initial values
//               (eq. 8); then the LM / quasi-Newton hybrid over the free parameters, on the same
//               whitened reprojection residuals as the bundle; covariance from the final Jacobian.
//   bundle      Ceres LM over the free parameters from the Tsai start (DLT if Tsai fails), priors,
//               robust loss, outliers, covariance and warnings (optim/bundle/bundle_adjustment.hpp).
// Parameters not free stay at: u0, v0 = the prior (else the image centre), sx = 1, distortion 0
// (SPEC §4.4: with a narrow field of view the principal point, rotation, f and Tz are nearly
// inseparable; docs/optimisation.md).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "config/mission_config.hpp"
#include "optim/bundle/bundle_adjustment.hpp"
#include "vision/camera/calibration_result.hpp"
#include "vision/camera/sensor_geometry.hpp"

namespace rangecal {

struct CalibrationProblem {
  std::string camera_id;
  SensorGeometry sensor;
  double nominal_focal_mm = 0;
  /// World points with their covariance and pixels with their σ (lamp track, control poles).
  std::vector<BundleObservation> observations;
  /// Ids of the control poles among the observations: they are the last control_pole_ids.size()
  /// observations, in this order (pipeline/stages/calibrate_stage.cpp make_calibration_problem).
  std::vector<std::string> control_pole_ids;
  CameraPriors priors;
  std::vector<std::string> free{"f", "k1", "pose"};
  double pixel_sigma_px = 0.1;
  std::uint64_t seed = 1;
};

/// Names accepted by calibrate_camera.
const std::vector<std::string>& calibration_method_names();

/// Runs `method` on `problem`. The result's reprojection statistics cover the observations the
/// method used; `rejected` lists the others. Throws rangecal::Error: usage for an unknown method
/// (or `planar`, which needs views of a planar target, not a lamp track); calibration when the
/// geometry is degenerate or the method fails.
CalibrationResult calibrate_camera(const std::string& method, const CalibrationProblem& problem);

/// Per-observation reprojection residual (projected − observed, px) of `cam`, each world point
/// moved to where the lamp stood at the true exposure time for a camera clock offset (s,
/// observed_world_point); NaN when a point cannot be projected.
std::vector<Eigen::Vector2d> reprojection_residuals(const Camera& cam,
                                                    const std::vector<BundleObservation>& obs,
                                                    double clock_offset_s = 0);
/// rms/mean/max of |residual| over the observations not in `rejected`.
ReprojectionStats reprojection_stats(const std::vector<Eigen::Vector2d>& residuals,
                                     const std::vector<std::size_t>& rejected);

}  // namespace rangecal
