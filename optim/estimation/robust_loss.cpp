#include "optim/estimation/robust_loss.hpp"

#include <ceres/loss_function.h>

namespace rangecal {

const char* to_string(RobustLoss loss) {
  switch (loss) {
    case RobustLoss::none:
      return "none";
    case RobustLoss::huber:
      return "huber";
    case RobustLoss::cauchy:
      return "cauchy";
  }
  return "none";
}

ceres::LossFunction* new_robust_loss(RobustLoss loss, double scale) {
  if (loss == RobustLoss::huber) return new ceres::HuberLoss(scale);
  if (loss == RobustLoss::cauchy) return new ceres::CauchyLoss(scale);
  return nullptr;
}

}  // namespace rangecal
