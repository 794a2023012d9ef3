#include "optim/network/network_cost_functions.hpp"

#include <algorithm>

#include "optim/bundle/projection_jacobian.hpp"

namespace rangecal {

ImageResidualCost::ImageResidualCost(const CameraBlock* camera, bool point_free,
                                     const Eigen::Vector3d& fixed_point, const Eigen::Vector3d& offset,
                                     const Eigen::Vector3d& velocity, const Eigen::Vector2d& pixel,
                                     const Eigen::Matrix2d& whitening)
    : camera_(camera),
      point_free_(point_free),
      fixed_point_(fixed_point),
      offset_(offset),
      velocity_(velocity),
      pixel_(pixel),
      whitening_(whitening) {
  set_num_residuals(2);
  if (camera_->size > 0) mutable_parameter_block_sizes()->push_back(camera_->size);
  if (point_free_) mutable_parameter_block_sizes()->push_back(3);
}

bool ImageResidualCost::Evaluate(double const* const* parameters, double* residuals,
                                 double** jacobians) const {
  const int n = camera_->size;
  const int point_block = n > 0 ? 1 : 0;
  if (!on_) {
    residuals[0] = residuals[1] = 0;
    if (jacobians && n > 0 && jacobians[0]) std::fill(jacobians[0], jacobians[0] + 2 * n, 0.0);
    if (jacobians && point_free_ && jacobians[point_block])
      std::fill(jacobians[point_block], jacobians[point_block] + 6, 0.0);
    return true;
  }
  // The camera at the evaluation point, expanded and its rotation formed once per evaluation
  // (CameraBlock::prepare_evaluation): Ceres passes the same values in parameters[0].
  const double* all = camera_->all.data();
  const Eigen::Vector3d X = point_free_
                                ? Eigen::Vector3d(Eigen::Map<const Eigen::Vector3d>(parameters[point_block]))
                                : fixed_point_;
  const bool want_camera = jacobians && n > 0 && jacobians[0];
  const bool want_point = jacobians && point_free_ && jacobians[point_block];
  Eigen::Vector2d uv;
  ProjectionJacobian pj;
  constexpr int kPose = kIntrinsicsBlockSize + kDistortionBlockSize;
  if (!project_with_jacobian(all, all + kIntrinsicsBlockSize, camera_->rotation, all + kPose + 3,
                             all[kBundleParameterCount - 1], camera_->dx_mm, camera_->dy_mm, X + offset_,
                             velocity_, &uv, want_camera || want_point ? &pj : nullptr))
    return false;
  Eigen::Map<Eigen::Vector2d> r(residuals);
  r = whitening_ * (uv - pixel_);
  if (want_camera) {
    double* J = jacobians[0];  // row-major 2 × n
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector2d col = whitening_ * pj.camera.col(camera_->index[static_cast<std::size_t>(j)]);
      J[j] = col.x(), J[n + j] = col.y();
    }
  }
  if (want_point) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jp(jacobians[point_block]);
    Jp = whitening_ * pj.world;
  }
  return true;
}

bool PointPriorCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Vector3d r = whitening_ * (Eigen::Map<const Eigen::Vector3d>(parameters[0]) - prior_);
  residuals[0] = half_ == 0 ? r[0] : r[2];
  residuals[1] = half_ == 0 ? r[1] : 0.0;
  if (jacobians && jacobians[0]) {
    Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J(jacobians[0]);
    if (half_ == 0) {
      J = whitening_.topRows<2>();
    } else {
      J.row(0) = whitening_.row(2);
      J.row(1).setZero();
    }
  }
  return true;
}

ParameterPriorCost::ParameterPriorCost(int block_size, std::vector<Term> terms)
    : block_size_(block_size), terms_(std::move(terms)) {
  set_num_residuals(static_cast<int>(terms_.size()));
  mutable_parameter_block_sizes()->push_back(block_size_);
}

bool ParameterPriorCost::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  const int m = static_cast<int>(terms_.size());
  for (int r = 0; r < m; ++r)
    residuals[r] = (parameters[0][terms_[static_cast<std::size_t>(r)].packed] -
                    terms_[static_cast<std::size_t>(r)].mean) /
                   terms_[static_cast<std::size_t>(r)].sigma;
  if (jacobians && jacobians[0]) {
    std::fill(jacobians[0], jacobians[0] + m * block_size_, 0.0);
    for (int r = 0; r < m; ++r)
      jacobians[0][r * block_size_ + terms_[static_cast<std::size_t>(r)].packed] =
          1 / terms_[static_cast<std::size_t>(r)].sigma;
  }
  return true;
}

}  // namespace rangecal
