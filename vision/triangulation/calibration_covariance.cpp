#include "vision/triangulation/calibration_covariance.hpp"

namespace rangecal {

CameraCovariance camera_covariance(const CalibrationResult& r, bool* usable) {
  const auto n = static_cast<Eigen::Index>(r.parameters.size());
  const bool ok = n > 0 && r.covariance.rows() == n && r.covariance.cols() == n && r.covariance.allFinite();
  if (usable) *usable = ok;
  if (!ok) return {};
  return {r.parameters, r.covariance};
}

}  // namespace rangecal
