#pragma once
// How well a calibration projects a point of the flight volume, from its parameter covariance
// (mrcal's projection uncertainty, docs/outputs.md "report.html"): a world point fixed at depth d
// along the ray of pixel q is projected through the camera while the free parameters θ vary with
// their covariance Σθ; to first order its pixel varies with Σq = J·Σθ·Jᵀ, J = ∂pixel/∂θ at that point
// (vision/triangulation/triangulation.hpp pixel_jacobian_wrt_parameters). A strongly correlated pair
// of parameters (f and the centre along the optical axis) barely moves such a point: this is what
// the intersection needs, whatever each parameter's own σ.
#include <Eigen/Core>
#include <vector>

#include "pipeline/io/correspondences_csv.hpp"
#include "vision/camera/calibration_result.hpp"

namespace rangecal {

/// The world point (ENU, m) at depth `depth_m` (along the optical axis, camera z) on the viewing ray
/// of pixel `uv_px` (u right, v down, top-left pixel centre (0, 0)).
Eigen::Vector3d point_on_pixel_ray(const Camera& cam, const Eigen::Vector2d& uv_px, double depth_m);

/// Σq (px²) of the projection of the world point `X_enu_m` through `cal` from its covariance. Zero
/// when the calibration has no covariance; NaN when the point is behind the camera.
Eigen::Matrix2d projection_covariance_px2(const CalibrationResult& cal, const Eigen::Vector3d& X_enu_m);

/// σ (px) of the projection of the point at depth `depth_m` on the ray of pixel `uv_px`: the
/// semi-major axis √λmax(Σq) of its 1σ error ellipse (the worst direction, as mrcal reports it).
double projection_sigma_px(const CalibrationResult& cal, const Eigen::Vector2d& uv_px, double depth_m);

/// projection_sigma_px over an nx × ny grid of pixel cells covering the image
/// [−0.5, W−0.5] × [−0.5, H−0.5]; values at the cell centres.
struct ProjectionUncertaintyMap {
  double depth_m = 0;
  std::vector<double> u_px;  ///< nx cell-centre columns (px)
  std::vector<double> v_px;  ///< ny cell-centre rows (px)
  Eigen::MatrixXd sigma_px;  ///< ny × nx (row = v)
};
ProjectionUncertaintyMap projection_uncertainty_map(const CalibrationResult& cal, double depth_m, int nx,
                                                    int ny);

/// The median depth (m, camera z) of the lamp pairs in front of `cam`: "the flight distance" the
/// uncertainty map is drawn at. NaN when no pair is in front.
double median_depth_m(const Camera& cam, const std::vector<Correspondence>& pairs);

}  // namespace rangecal
