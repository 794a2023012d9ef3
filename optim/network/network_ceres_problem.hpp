#pragma once
// The network's Ceres problem, built once and solved twice: the robust solve that separates the
// outliers and the least-squares solve without them (network_adjustment.cpp). Building a problem
// and freeing it cost as much as an iteration (docs/performance.md, network bundle); between the solves only
// the loss, the weights of the single-view observations and the set of observations and priors change, and
// those are changed in place: a residual that leaves the solve is switched off (r = 0, J = 0), a point left
// with one camera's ray becomes that camera's single-view residual (network_parameters.hpp), and a point left
// with nothing is held constant (docs/performance.md, network bundle). Under a correlated PPK model it
// solves the model's white approximation (network_adjustment.cpp; the model's own solve is
// network_gauss_newton.hpp).
#include <ceres/evaluation_callback.h>
#include <ceres/loss_function.h>
#include <ceres/problem.h>

#include <array>
#include <memory>
#include <vector>

#include "optim/network/camera_block.hpp"
#include "optim/network/network_cost_functions.hpp"
#include "optim/network/network_parameters.hpp"

namespace rangecal {

class NetworkCeresProblem {
 public:
  /// The problem of `selection` over `blocks` (whose point arrays the solves update in place).
  NetworkCeresProblem(const NetworkLayout& layout, NetworkParameterBlocks* blocks,
                      const NetworkSelection& selection);
  NetworkCeresProblem(const NetworkCeresProblem&) = delete;
  NetworkCeresProblem& operator=(const NetworkCeresProblem&) = delete;

  /// Takes `selection` (a subset of the one before: observations and priors only leave) and the
  /// cameras of `blocks` as the next solve's start.
  void select(const NetworkSelection& selection);

  /// One Levenberg–Marquardt solve with `loss` (Schur elimination of the points) to relative
  /// tolerance `tolerance`; writes the cameras back into the blocks, rotations re-based. Returns the
  /// iterations.
  int solve(RobustLoss loss, double loss_scale, double tolerance, int max_iterations, int num_threads);

 private:
  void add_image_residual(std::size_t i, const NetworkSelection& selection);
  void pack_cameras();

  /// Before each evaluation, every camera's evaluation point (CameraBlock::prepare_evaluation):
  /// Ceres has then written the point it evaluates at into the camera blocks.
  class CameraEvaluation final : public ceres::EvaluationCallback {
   public:
    explicit CameraEvaluation(std::vector<CameraBlock>* cameras) : cameras_(cameras) {}
    void PrepareForEvaluation(bool, bool) override {
      for (CameraBlock& c : *cameras_) c.prepare_evaluation();
    }

   private:
    std::vector<CameraBlock>* cameras_;
  };

  const NetworkLayout& layout_;
  NetworkParameterBlocks* blocks_;
  std::vector<CameraBlock> cameras_;  // sized once: the costs point into it
  CameraEvaluation evaluation_{&cameras_};
  ceres::LossFunctionWrapper loss_{nullptr, ceres::TAKE_OWNERSHIP};  // the image and prior residuals' loss
  std::unique_ptr<ceres::Problem> problem_;
  std::vector<ImageResidualCost*> image_;              // per observation: its residual (null: none)
  std::vector<char> image_single_view_;                // per observation: its residual is the single-view one
  std::vector<std::array<PointPriorCost*, 2>> prior_;  // per point: its prior's two halves
  std::vector<char> point_constant_;
};

}  // namespace rangecal
