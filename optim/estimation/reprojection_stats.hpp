#pragma once
// The reprojection statistics of a calibration (ReprojectionStats,
// vision/camera/calibration_result.hpp) from the pixel residuals of its observations.
#include <Eigen/Core>
#include <vector>

#include "vision/camera/calibration_result.hpp"

namespace rangecal {

/// rms, mean and max of ‖e_i‖ (px) over the observations with used[i]; n_used, and n_rejected the
/// others. rms/mean/max stay NaN when none is used.
ReprojectionStats reprojection_stats(const std::vector<Eigen::Vector2d>& residual_px,
                                     const std::vector<char>& used);

}  // namespace rangecal
