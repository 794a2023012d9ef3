#pragma once
// The difference between two calibrations of one camera (`rangecal compare-calibrations`, mrcal's
// projection difference): a world point at depth d on calibration A's viewing ray of pixel q is
// projected through both, Δ = q_B − q_A (px), and judged against the combined projection covariance
// S = Σq_A + Σq_B (pipeline/report/projection_uncertainty.hpp) by its Mahalanobis length
// m = √(Δᵀ S⁻¹ Δ). With both calibrations drawn from one distribution (two Monte Carlo trials) m²
// is χ² with 2 degrees of freedom, so m > kDifferenceExceeds (√χ²₂(0.95)) at 5 % of the pixels on
// average: above that rate the two calibrations disagree by more than their σ explains.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "vision/camera/calibration_result.hpp"

namespace rangecal {

/// √χ²₂(0.95) = √(−2 ln 0.05): the Mahalanobis length a 2-D Gaussian exceeds with probability 5 %.
inline constexpr double kDifferenceExceeds = 2.447746830680816;

struct DifferenceCell {
  Eigen::Vector2d uv_px = Eigen::Vector2d::Zero();    ///< cell centre (px), in A's image
  Eigen::Vector2d diff_px = Eigen::Vector2d::Zero();  ///< q_B − q_A (px); NaN where B cannot project
  double sigma_px = 0;     ///< √λmax(S): the combined 1σ in the worst direction (px)
  double mahalanobis = 0;  ///< √(Δᵀ S⁻¹ Δ); 0 when Δ = 0, infinite when Δ ≠ 0 and S = 0
  bool exceeds = false;    ///< mahalanobis > kDifferenceExceeds
};

struct CalibrationDifference {
  double depth_m = 0;
  int nx = 0, ny = 0;
  std::vector<DifferenceCell> cells;  ///< row-major: v rows top to bottom, u columns left to right
  double max_diff_px = 0;             ///< largest |Δ| (px)
  double rms_diff_px = 0;             ///< RMS |Δ| over cells (px)
  double fraction_exceeding = 0;      ///< share of cells with `exceeds`
};

/// Compares `a` and `b` over an nx × ny grid of cells covering the image, at depth `depth_m` (m,
/// > 0). Throws rangecal::Error (input) when the image sizes differ, naming `file_b`.
CalibrationDifference compare_calibrations(const CalibrationResult& a, const CalibrationResult& b,
                                           double depth_m, int nx, int ny, const std::string& file_b = "");

/// The depth (m) of the site origin (ENU 0, 0, 0) in camera `cam`: where the range's poles and
/// flights are, the default comparison depth. NaN when the origin is behind the camera.
double site_origin_depth_m(const Camera& cam);

/// The console table: one line per grid row, |Δ| per cell (px, "%.3f"), a '*' after cells that
/// exceed, then the summary (max, RMS, share exceeding).
std::string format_difference_table(const CalibrationDifference& d);

}  // namespace rangecal
