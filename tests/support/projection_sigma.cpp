#include "support/projection_sigma.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "vision/camera/camera_model.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal::test {

double finite_difference_projection_sigma_px(const CalibrationResult& r, const Eigen::Vector3d& X) {
  const Eigen::VectorXd x0 = parameter_values(r.camera, r.parameters, r.clock_offset_s);
  Eigen::MatrixXd J(2, x0.size());
  for (Eigen::Index k = 0; k < x0.size(); ++k) {
    const double h = 1e-4 * std::sqrt(r.covariance(k, k));
    Eigen::VectorXd xp = x0, xm = x0;
    xp[k] += h;
    xm[k] -= h;
    Eigen::Vector2d up, um;
    if (!project(camera_with_parameters(r.camera, r.parameters, xp), X, &up) ||
        !project(camera_with_parameters(r.camera, r.parameters, xm), X, &um)) {
      ADD_FAILURE() << "the point does not project at a parameter step " << k;
      return std::numeric_limits<double>::quiet_NaN();
    }
    J.col(k) = (up - um) / (2 * h);
  }
  const Eigen::Matrix2d S = J * r.covariance * J.transpose();
  return std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(S).eigenvalues().maxCoeff());
}

}  // namespace rangecal::test
