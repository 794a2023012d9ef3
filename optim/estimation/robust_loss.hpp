#pragma once
// The robust loss of a solve (docs/optimisation.md "Outliers"), shared by the per-camera bundle and
// the network: Huber (quadratic below the scale, linear above) or Cauchy on the whitened residual,
// the scale in σ units.
namespace ceres {
class LossFunction;
}

namespace rangecal {

enum class RobustLoss { none, huber, cauchy };
const char* to_string(RobustLoss loss);

/// A new Ceres loss of kind `loss` and scale `scale` (σ units); null for RobustLoss::none (plain
/// least squares). The caller owns it.
ceres::LossFunction* new_robust_loss(RobustLoss loss, double scale);

}  // namespace rangecal
