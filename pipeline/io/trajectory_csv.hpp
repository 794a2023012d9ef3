#pragma once
// <out>/trajectory.csv, the trajectory stage's table (docs/outputs.md "trajectory.csv"; method in
// docs/trajectory.md): one row per instant with the target triangulated from two or more cameras.
//   utc                      ISO 8601, ns
//   E,N,U                    site ENU (m)
//   lat,lon,h                WGS84 degrees, ellipsoidal height (m) of that point
//   sigma_E,sigma_N,sigma_U  1σ (m), total: labels + timing + calibration
//   cov_EN,cov_EU,cov_NU     the total covariance's off-diagonal (m²)
//   sigma_m                  √trace of the covariance: the predicted rms of the 3-D error (m)
//   sigma_labels_m, sigma_timing_m, sigma_calibration_m   √trace of each part (m)
//   vE,vN,vU                 velocity (m/s): the smoother's, else a central difference; blank without
//                            neighbours
//   sigma_vE,sigma_vN,sigma_vU   their 1σ (m/s)
//   aE,aN,aU                 acceleration (m/s²), from the smoother's state; blank without it
//   sigma_aE,sigma_aN,sigma_aU   their 1σ (m/s²)
//   cameras                  the cameras whose labels were used, joined by '+'
//   rms_px                   the views' reprojection rms (px)
//   chi2,dof                 the views' χ² under their label and timing σ, and 2·views − 3
//   inflated                 1: χ² above its 99 % quantile, every σ above scaled by √(χ²/dof)
//   extrapolated             the cameras whose label lies outside the image region their calibration saw
//                            (joined by '+'; blank: none): the lens model is extrapolated there
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gnss/geodesy/local_enu.hpp"
#include "gnss/time/utc_time.hpp"
#include "vision/triangulation/target_trajectory.hpp"

namespace rangecal {

/// The CSV text of `trajectory`, geodetic columns through `site`.
std::string format_trajectory_csv(const Trajectory& trajectory, const LocalEnu& site);

/// Writes it atomically (a failed write leaves no partial file).
void write_trajectory_csv(const std::string& path, const Trajectory& trajectory, const LocalEnu& site);

/// One row read back (the report's trajectory section): what the report shows of it.
struct TrajectoryRow {
  UtcTime utc;
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();     ///< m
  Eigen::Matrix3d cov_m2 = Eigen::Matrix3d::Zero();  ///< total covariance (m²)
  double sigma_m = 0;                                ///< √trace
  double sigma_labels_m = 0, sigma_timing_m = 0, sigma_calibration_m = 0;
  std::vector<std::string> cameras;
  double rms_px = 0;
  bool inflated = false;
  std::vector<std::string> extrapolated;
};

/// Parses the CSV text written by format_trajectory_csv; `path` names it in messages. Throws
/// rangecal::Error (input) naming the file, line and column of a missing column or a bad cell.
std::vector<TrajectoryRow> parse_trajectory_csv(const std::string& text, const std::string& path);
std::vector<TrajectoryRow> read_trajectory_csv(const std::string& path);

}  // namespace rangecal
