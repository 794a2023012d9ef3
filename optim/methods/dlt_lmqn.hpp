#pragma once
// `dlt_lmqn` (docs/optimisation.md; seed 000): the normalised DLT with RANSAC (vision/calibration/dlt.hpp)
// gives K, R, C; the free distortion terms start from their linear least-squares values (seed 000
// eq. 8, vision/calibration/linear_distortion.hpp); then the LM / quasi-Newton hybrid
// (optim/search/lm_qn.hpp, seed 000 §3) minimises the same whitened reprojection residuals as the
// bundle (each pixel residual whitened by C = σ_px²·I + J_X·Σ_X·J_Xᵀ, optim/bundle/bundle_adjustment.hpp)
// over the free parameters, in z = (x − x0)/scale with the vocabulary's search scales
// (vision/camera/camera_parameters.hpp) because LM's damping μI is not scale invariant. The
// whitening C is taken once, at the DLT start (`start`), and kept: the covariance is (JᵀJ)⁻¹ of the
// Jacobian at the solution whitened by those weights, the covariance of the objective minimised.
//
// Outliers: RANSAC gates on the distortion-free DLT model at 4 px (the PPK noise of the lamp alone
// projects to ~1 px at range, so a 2 px gate would reject good points); once LM-QN has fitted the
// distortion every point is re-judged by its whitened residual (> 4σ after robust scaling by the
// median) and the fit repeated while the inlier set changes (at most 4 rounds).
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "optim/bundle/bundle_adjustment.hpp"
#include "optim/search/lm_qn.hpp"
#include "vision/calibration/dlt.hpp"
#include "vision/camera/camera_parameters.hpp"
#include "vision/camera/sensor_geometry.hpp"

namespace rangecal {

struct DltLmqnOptions {
  /// Parameters LM-QN estimates (clock_offset is not among them: the method takes the frame time
  /// stamps as exact); the others are held (hold_fixed_intrinsics).
  std::vector<CameraParameter> free{CameraParameter::f,  CameraParameter::k1, CameraParameter::wx,
                                    CameraParameter::wy, CameraParameter::wz, CameraParameter::CE,
                                    CameraParameter::CN, CameraParameter::CU};
  Eigen::Vector2d fixed_principal_point_px = Eigen::Vector2d::Zero();  ///< u0, v0 when not free (px)
  double pixel_sigma_px = 0.1;       ///< σ of a pixel whose observation gives none (px)
  std::uint64_t seed = 1;            ///< RANSAC sampling
  double ransac_threshold_px = 4.0;  ///< RANSAC inlier gate on the DLT model (px)
  double outlier_sigma = 4.0;        ///< whitened residual above this × robust scale → outlier
};

struct DltLmqnResult {
  DltResult dlt;                            ///< the linear start
  LmQnResult lmqn;                          ///< the last LM-QN solve (in z)
  Camera start;                             ///< the DLT start; the whitening is taken there
  Camera camera;                            ///< the calibrated camera
  std::vector<std::size_t> used;            ///< observations in the final fit, ascending
  std::vector<std::size_t> rejected;        ///< the others, ascending
  std::vector<CameraParameter> parameters;  ///< the estimated parameters (covariance order)
  Eigen::MatrixXd covariance;               ///< empty when the normal matrix is rank-deficient
};

/// Runs the method on `observations` (world ENU m with Σ_X, pixel with σ). Throws rangecal::Error
/// (calibration) on degenerate input (from the DLT) or fewer residuals than free parameters.
DltLmqnResult dlt_lmqn_calibrate(const std::vector<BundleObservation>& observations,
                                 const SensorGeometry& sensor, const DltLmqnOptions& options);

}  // namespace rangecal
