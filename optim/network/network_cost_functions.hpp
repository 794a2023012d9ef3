#pragma once
// The Ceres cost functions the network solves with: the image residual of
// optim/bundle/reprojection_cost.hpp's ReprojectionResidual (with the point as a fifth block, or
// the single-view residual with the point eliminated), the point priors and the camera priors, over
// one block per camera (camera_block.hpp), with the derivatives written out
// (optim/bundle/projection_jacobian.hpp) instead of automatic differentiation of the 21-parameter
// functor (docs/performance.md, network bundle). The functor stays the definition;
// tests/unit/optim/projection_jacobian_test.cpp holds the two equal.
#include <ceres/cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <vector>

#include "optim/network/camera_block.hpp"

namespace rangecal {

/// r = W·(project(X + offset − v·δ) − uv): with `point_free` X is the parameter block after the
/// camera's (ENU m, the network's point) and W = I/σ_px; otherwise X is fixed (`fixed_point`) and W
/// the single-view whitening (network_parameters.hpp). The camera block is left out when it has
/// no free parameter.
class ImageResidualCost final : public ceres::CostFunction {
 public:
  ImageResidualCost(const CameraBlock* camera, bool point_free, const Eigen::Vector3d& fixed_point,
                    const Eigen::Vector3d& offset, const Eigen::Vector3d& velocity,
                    const Eigen::Vector2d& pixel, const Eigen::Matrix2d& whitening);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  /// A new W (the single-view whitening at the next solve's start cameras).
  void set_whitening(const Eigen::Matrix2d& whitening) { whitening_ = whitening; }
  /// Takes the residual out of the solve: r = 0 and J = 0 from now on (network_ceres_problem.hpp).
  void switch_off() { on_ = false; }

 private:
  const CameraBlock* camera_;
  bool point_free_;
  bool on_ = true;
  Eigen::Vector3d fixed_point_, offset_, velocity_;
  Eigen::Vector2d pixel_;
  Eigen::Matrix2d whitening_;
};

/// Prior of a point (PPK fix or pole survey), r = L⁻¹·(X − X̄) with L·Lᵀ = Σ_prior (full 3 × 3), as
/// two 2-row residual blocks: half 0 is (r0, r1), half 1 is (r2, 0). With every residual block on a point
/// two rows high, Ceres eliminates the points with its fixed-size ⟨2, 3, ·⟩ Schur eliminator
/// (docs/performance.md, network bundle); under the robust loss each half is weighed on its own (the
/// whitened horizontal pair and the vertical).
class PointPriorCost final : public ceres::SizedCostFunction<2, 3> {
 public:
  PointPriorCost(const Eigen::Vector3d& prior, const Eigen::Matrix3d& whitening, int half)
      : prior_(prior), whitening_(whitening), half_(half) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  /// Takes the prior out of the solve (whitening 0: r = 0, J = 0).
  void switch_off() { whitening_.setZero(); }

 private:
  Eigen::Vector3d prior_;
  Eigen::Matrix3d whitening_;
  int half_;
};

/// Priors on single parameters of one camera block: r_m = (x[j_m] − mean_m)/σ_m (the principal
/// point and centre priors of reprojection_cost.hpp on whichever of them are free).
class ParameterPriorCost final : public ceres::CostFunction {
 public:
  struct Term {
    int packed = 0;  ///< index in the camera block
    double mean = 0, sigma = 1;
  };
  ParameterPriorCost(int block_size, std::vector<Term> terms);
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  int block_size_;
  std::vector<Term> terms_;
};

}  // namespace rangecal
