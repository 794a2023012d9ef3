#include "support/network_honesty.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rangecal::test {

using Eigen::MatrixXd;
using Eigen::VectorXd;

void add_mission(const CrbNetwork& n, const NetworkResult& r, const CameraJointCovariance& bound,
                 const std::vector<Eigen::Vector3d>& volume, HonestyFigures* f) {
  CameraJointCovariance predicted = bound, error = bound;
  predicted.joint = MatrixXd::Zero(bound.joint.rows(), bound.joint.cols());
  VectorXd err(bound.joint.rows());
  for (std::size_t c = 0; c < n.cameras.size(); ++c) {
    const CalibrationResult& cal = r.cameras[c].calibration;
    const VectorXd e = free_values(n, c, cal.camera) - free_values(n, c, n.cameras[c].truth);
    err.segment(bound.offset[c], e.size()) = e;
    // The network's joint covariance in the bound's order, cross-camera blocks included.
    const std::vector<CameraParameter>& mine = n.cameras[c].free;
    for (std::size_t c2 = 0; c2 < n.cameras.size(); ++c2) {
      const CalibrationResult& cal2 = r.cameras[c2].calibration;
      const std::vector<CameraParameter>& other = n.cameras[c2].free;
      for (std::size_t a = 0; a < mine.size(); ++a)
        for (std::size_t b = 0; b < other.size(); ++b)
          predicted.joint(bound.offset[c] + static_cast<Eigen::Index>(a),
                          bound.offset[c2] + static_cast<Eigen::Index>(b)) =
              r.joint_covariance(r.joint_offset[c] + cal.parameter_index(mine[a]),
                                 r.joint_offset[c2] + cal2.parameter_index(other[b]));
    }
    // z-scores of f and the centre (CE, CN, CU).
    const VectorXd s = r.cameras[c].details.sigma_unscaled;
    for (CameraParameter p :
         {CameraParameter::f, kCenterParameters[0], kCenterParameters[1], kCenterParameters[2]}) {
      std::size_t a = 0;
      while (a < mine.size() && mine[a] != p) ++a;
      const double z = e[static_cast<Eigen::Index>(a)] / s[cal.parameter_index(p)];
      f->z_rms += z * z;
      f->z_worst = std::max(f->z_worst, std::abs(z));
      ++f->z_count;
    }
  }
  error.joint = err * err.transpose();
  f->actual_m += std::pow(intersection_sigma_m(n, error, volume), 2);
  f->predicted_m += std::pow(intersection_sigma_m(n, predicted, volume), 2);
  ++f->missions;
}

void finish(const CrbNetwork& n, const CameraJointCovariance& bound,
            const std::vector<Eigen::Vector3d>& volume, HonestyFigures* f) {
  f->actual_m = std::sqrt(f->actual_m / f->missions),
  f->predicted_m = std::sqrt(f->predicted_m / f->missions);
  f->z_rms = std::sqrt(f->z_rms / f->z_count);
  f->bound_m = intersection_sigma_m(n, bound, volume);
}

void print(const char* what, const HonestyFigures& f) {
  std::printf(
      "  %-10s intersection error rms %.3f cm, predicted %.3f cm (x%.2f), bound %.3f cm (x%.2f); z rms "
      "%.2f, worst %.1f\n",
      what, 100 * f.actual_m, 100 * f.predicted_m, f.actual_m / f.predicted_m, 100 * f.bound_m,
      f.actual_m / f.bound_m, f.z_rms, f.z_worst);
}

}  // namespace rangecal::test
