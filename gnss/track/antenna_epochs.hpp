#pragma once
// Antenna epochs: the solutions of every .pos file of a mission, in site ENU, merged into one
// time-ordered sequence (docs/gnss.md). This is the input of filtering and of the lever arm.
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "gnss/formats/rtklib_pos_reader.hpp"
#include "gnss/geodesy/local_enu.hpp"

namespace rangecal {

struct AntennaEpoch {
  UtcTime utc;
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();       ///< antenna phase centre, site ENU (m)
  Eigen::Matrix3d cov_enu = Eigen::Matrix3d::Zero();   ///< its covariance, site ENU (m²)
  Eigen::Vector3d sd_local = Eigen::Vector3d::Zero();  ///< (sdE, sdN, sdU) in the epoch's local ENU (m)
  Eigen::Vector3d vel_enu =
      Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());  ///< m/s or NaN
  int quality = 0;                                                          ///< RTKLIB Q
  int ns = 0;
  int file_index = 0;  ///< index into the list of .pos files
  long line = 0;       ///< 1-based line in that file
};

/// Converts every epoch of `files` to site ENU and merges them in time order. Two epochs at the
/// same instant (overlapping files) are an error (rangecal::Error, input) naming both files and
/// lines: which solution to trust is the user's choice, not ours.
std::vector<AntennaEpoch> merge_antenna_epochs(const std::vector<PosFile>& files, const LocalEnu& site);

}  // namespace rangecal
