#pragma once
// What report.html's trajectory section says of trajectory.csv (docs/outputs.md, docs/trajectory.md):
// how many instants over what span, the σ and their parts, the instants whose views disagreed
// (inflated) or rest on an extrapolated lens model, each camera's share, and the stretches — runs of
// instants with no gap and one set of cameras — so a gap or a camera dropping out is seen at once.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "pipeline/io/trajectory_csv.hpp"

namespace rangecal {

/// A run of instants without a gap (no step above kTrajectoryGapSteps median steps) seen by one set
/// of cameras. Times in seconds since the first instant.
struct TrajectoryStretch {
  double start_s = 0, end_s = 0;
  std::vector<std::string> cameras;
  int instants = 0;
};

struct TrajectoryCameraUse {
  std::string id;
  int instants = 0;      ///< instants whose fix used its label
  int extrapolated = 0;  ///< of them, where its label lay outside its calibration's coverage
};

struct TrajectorySummary {
  int instants = 0;
  double span_s = 0;  ///< first to last instant
  double step_s = 0;  ///< median step between instants
  double sigma_median_m = 0, sigma_p95_m = 0;
  double labels_median_m = 0, timing_median_m = 0, calibration_median_m = 0;
  int inflated = 0;      ///< instants whose views disagreed beyond their σ (σ scaled up)
  int extrapolated = 0;  ///< instants with some camera's label outside its calibration's coverage
  std::vector<TrajectoryCameraUse> cameras;  ///< in order of first use
  std::vector<TrajectoryStretch> stretches;
};

/// A step between instants above this many median steps is a gap.
inline constexpr double kTrajectoryGapSteps = 2.5;

/// The summary of `rows` (in time order); all zero for none.
TrajectorySummary summarise_trajectory(const std::vector<TrajectoryRow>& rows);

/// A 2-D 1σ ellipse: semi-axes (m) and the major axis' angle from the first axis towards the
/// second (degrees, in (−90, 90]).
struct SigmaEllipse {
  double major_m = 0, minor_m = 0, angle_deg = 0;
};
SigmaEllipse sigma_ellipse(const Eigen::Matrix2d& cov_m2);

}  // namespace rangecal
