#pragma once
// The per-camera bundle's image residual as the Ceres cost function it solves with:
// ReprojectionResidual (reprojection_cost.hpp, the definition) over the four camera blocks, with the
// derivatives written out (projection_jacobian.hpp) instead of automatic differentiation of the
// 18-parameter functor (docs/performance.md). tests/unit/optim/projection_jacobian_test.cpp holds
// the two equal.
#include <ceres/sized_cost_function.h>

#include "optim/bundle/reprojection_cost.hpp"

namespace rangecal {

class ReprojectionCostFunction final
    : public ceres::SizedCostFunction<2, kIntrinsicsBlockSize, kDistortionBlockSize, kPoseBlockSize,
                                      kClockBlockSize> {
 public:
  explicit ReprojectionCostFunction(const ReprojectionResidual& residual) : r_(residual) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  ReprojectionResidual r_;
};

}  // namespace rangecal
