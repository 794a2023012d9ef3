#pragma once
// The result every calibration method returns (docs/optimisation.md, docs/outputs.md): the calibrated camera,
// the covariance of the estimated parameters, reprojection statistics, warnings and method-specific details.
// One value type for every method, written to `<cam>/calibration.json` by pipeline/io/calibration_json.hpp.
//
// The estimated parameters are named by vision/camera/camera_parameters.hpp (a method lists only
// those it estimated; `covariance` rows and columns follow `parameters`). The camera centre's
// covariance is always given separately (`center_covariance_m2`), propagated from whichever pose
// parameters the method used (see center_covariance_from_pose).
#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gnss/geodesy/geodetic_origin.hpp"
#include "vision/camera/camera_model.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal {

/// Reprojection error statistics over the observations (pixels). rms/mean/max are over the
/// observations used in the final fit; n_rejected counts those rejected as outliers.
struct ReprojectionStats {
  double rms_px = std::numeric_limits<double>::quiet_NaN();
  double mean_px = std::numeric_limits<double>::quiet_NaN();
  double max_px = std::numeric_limits<double>::quiet_NaN();
  int n_used = 0;
  int n_rejected = 0;
};

struct CalibrationResult {
  std::string camera_id;  ///< the camera's id from the mission config
  std::string method;     ///< tsai | tsai_sassa | dlt_lmqn | bundle | planar
  Camera camera;          ///< the calibrated camera (intrinsics in mm/px, pose world→camera)
  /// Camera clock − GNSS time (s): estimated when `clock_offset` is a free parameter, else 0. The
  /// lamp pixels of this camera were seen at stamp − clock_offset_s (optim/bundle/bundle_adjustment.hpp).
  double clock_offset_s = 0;
  /// The site origin the camera's world ENU frame is tangent at (gnss/geodesy/local_enu.hpp), so
  /// that the pose can be placed on the Earth; set by the calibrate stage from the mission's
  /// site.origin, empty for results that were never tied to a site (and in older files).
  std::optional<GeodeticOrigin> site_origin;

  /// The estimated parameters, in covariance order.
  std::vector<CameraParameter> parameters;
  /// Covariance of those parameters in their units; empty (0×0) when not computed.
  Eigen::MatrixXd covariance;
  /// Covariance of the camera centre C = −Rᵀ·T in ENU (m²); NaN when not computed.
  Eigen::Matrix3d center_covariance_m2 = Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());

  ReprojectionStats reprojection;
  /// Indices (into the method's input observations) of the points rejected as outliers.
  std::vector<std::size_t> rejected;
  /// Human-readable warnings (poorly determined parameters, high correlations, …).
  std::vector<std::string> warnings;
  /// Method-specific details (e.g. SSA: start, ‖z‖, evaluations, polish; DLT: RANSAC inliers).
  /// Must be deterministic (no wall times) so calibration.json is byte-identical across runs.
  nlohmann::json details = nlohmann::json::object();
  /// Wall time of the method (s), for methods.csv; not written to calibration.json.
  double wall_time_s = 0;

  /// Index of `p` in parameters, or -1.
  int parameter_index(CameraParameter p) const {
    for (std::size_t i = 0; i < parameters.size(); ++i)
      if (parameters[i] == p) return static_cast<int>(i);
    return -1;
  }
  /// 1σ of parameter `p` in its unit; NaN when it was not estimated or no covariance exists.
  double sigma(CameraParameter p) const {
    const int i = parameter_index(p);
    if (i < 0 || covariance.rows() != static_cast<Eigen::Index>(parameters.size()) ||
        covariance.cols() != covariance.rows())
      return std::numeric_limits<double>::quiet_NaN();
    return std::sqrt(covariance(i, i));
  }
  /// Correlation of two estimated parameters; NaN when either is unavailable.
  double correlation(CameraParameter a, CameraParameter b) const {
    const int i = parameter_index(a), j = parameter_index(b);
    const double si = sigma(a), sj = sigma(b);
    if (i < 0 || j < 0 || !(si > 0) || !(sj > 0)) return std::numeric_limits<double>::quiet_NaN();
    return covariance(i, j) / (si * sj);
  }
  /// 1σ of the camera centre in E, N, U (m); NaN when not computed.
  Eigen::Vector3d center_sigma_m() const { return center_covariance_m2.diagonal().cwiseSqrt(); }
};

/// Propagates the covariance of pose parameters (wx, wy, wz, Tx, Ty, Tz) — rotation perturbation
/// R = exp([w]×)·R̂ in rad, translation in m — to the camera centre C = −Rᵀ·T (m²).
/// First order: dC/dT = −R̂ᵀ, dC/dw = −R̂ᵀ·[T]× (from Rᵀ ≈ R̂ᵀ(I − [w]×)).
inline Eigen::Matrix3d center_covariance_from_pose(const Eigen::Matrix3d& R, const Eigen::Vector3d& T,
                                                   const Eigen::Matrix<double, 6, 6>& cov_wT) {
  Eigen::Matrix3d Tx;
  Tx << 0, -T.z(), T.y(), T.z(), 0, -T.x(), -T.y(), T.x(), 0;
  Eigen::Matrix<double, 3, 6> J;
  J.leftCols<3>() = -R.transpose() * Tx;
  J.rightCols<3>() = -R.transpose();
  return J * cov_wT * J.transpose();
}

}  // namespace rangecal
