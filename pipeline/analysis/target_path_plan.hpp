#pragma once
// The trajectory σ a target's planned path would get (docs/accuracy_analysis.md "A target's path"),
// before flying: the cameras at their scenario stations, calibrated together on the scenario's
// routes (the network's Cramér–Rao bound, cross blocks between cameras included), then at every
// instant of the path each camera that sees the target gives a view with the stated label σ and
// timing σ (its image velocity from the path's), triangulated as the trajectory stage would
// (vision/triangulation/triangulation.hpp). The σ is the one the trajectory stage states, parts
// and all, at noise-free labels: what the geometry, the labels, the clocks and the calibration
// allow.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "pipeline/io/target_path_csv.hpp"
#include "vision/camera/camera_model.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal {

struct TargetPathOptions {
  double label_sigma_px = 0.5;    ///< a label's 1σ per axis (px, > 0)
  double timing_sigma_s = 0.001;  ///< a label's instant's 1σ (s, ≥ 0)
  double rate_hz = 10;            ///< instants per second along the path (> 0)
};

struct PlannedTargetInstant {
  double t_s = 0;                                          ///< s since the path's start
  Eigen::Vector3d enu_m = Eigen::Vector3d::Zero();         ///< the planned position (m)
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();  ///< the path's (m/s)
  std::vector<std::size_t> cameras;                        ///< the cameras that see it (indices)
  Eigen::Matrix3d cov_m2 = Eigen::Matrix3d::Zero();        ///< the total covariance (m²)
  double sigma_m = 0;                                      ///< √trace: the predicted rms of the 3-D error
  double labels_m = 0, timing_m = 0, calibration_m = 0;    ///< √trace of each part
};

struct PlannedTargetPath {
  std::vector<PlannedTargetInstant> instants;  ///< seen by two or more cameras
  std::size_t tried = 0;                       ///< instants on the path
  std::size_t unseen = 0;                      ///< of them, seen by fewer than two cameras
};

/// Throws rangecal::Error (config) naming the command-line option of a value out of range, or
/// --target-rate when `path` at that rate would be more than 1,000,000 instants.
void check_target_path_options(const TargetPathOptions& options, const std::vector<TargetPathPoint>& path);

/// The path's instants every 1/rate_hz s from its first waypoint's time to its last, each
/// triangulated from the cameras `truth` that see it. `joint` is the cameras' joint calibration
/// covariance, cameras in order, each block over `parameters` (network_cramer_rao_bound); an
/// instant whose rays are nearly parallel is counted unseen. Throws as check_target_path_options.
PlannedTargetPath plan_target_path(const std::vector<Camera>& truth,
                                   const std::vector<CameraParameter>& parameters,
                                   const Eigen::MatrixXd& joint, const std::vector<TargetPathPoint>& path,
                                   const TargetPathOptions& options);

}  // namespace rangecal
