#pragma once
// The part of a camera's image its calibration saw: the cells of a square grid that hold at least one
// of its calibration observations. A lens model fitted there is extrapolated beyond it — a polynomial
// distortion most of all near the image edges — and its covariance, which assumes the model is right,
// does not say how far off it may be (docs/trajectory.md "Extrapolated views").
#include <Eigen/Core>
#include <set>
#include <utility>
#include <vector>

namespace rangecal {

class ImageCoverage {
 public:
  ImageCoverage() = default;
  /// `pixels` (px) on a grid of `cell_px`-wide cells (> 0).
  ImageCoverage(const std::vector<Eigen::Vector2d>& pixels, double cell_px);
  bool empty() const { return cells_.empty(); }
  /// The pixel lies in a covered cell or one of its eight neighbours. An empty coverage (nothing
  /// known) covers everything.
  bool covers(const Eigen::Vector2d& uv_px) const;
  /// How far (px) the pixel lies outside the covered region (covered cells and their neighbours):
  /// 0 inside it or for an empty coverage, +inf for a pixel not finite.
  double distance_outside_px(const Eigen::Vector2d& uv_px) const;

 private:
  double cell_px_ = 1;
  std::set<std::pair<long, long>> cells_;
};

}  // namespace rangecal
