#include "optim/estimation/center_covariance.hpp"

#include <limits>

namespace rangecal {

Eigen::Matrix3d center_covariance(const CalibrationResult& result) {
  if (result.covariance.rows() != static_cast<Eigen::Index>(result.parameters.size()))
    return Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Matrix3d cc = Eigen::Matrix3d::Zero();
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const int ia = result.parameter_index(kCenterParameters[a]);
      const int ib = result.parameter_index(kCenterParameters[b]);
      if (ia >= 0 && ib >= 0) cc(a, b) = result.covariance(ia, ib);
    }
  return cc;
}

}  // namespace rangecal
