#include "optim/network/network_ceres_problem.hpp"

#include <ceres/solver.h>

#include <cmath>

#include "config/error.hpp"

namespace rangecal {
namespace {

/// The packed index of canonical parameter `p` in `camera`, or −1 when it is not free.
int packed_index(const CameraBlock& camera, CameraParameter p) {
  for (int j = 0; j < camera.size; ++j)
    if (camera.index[static_cast<std::size_t>(j)] == index_of(p)) return j;
  return -1;
}

/// The principal-point and centre priors on whichever of those parameters are free.
std::vector<ParameterPriorCost::Term> camera_prior_terms(const CameraBlock& camera, const BundleSetup& s,
                                                         const BundlePriors& pr) {
  std::vector<ParameterPriorCost::Term> terms;
  auto add = [&](CameraParameter p, double mean, double sigma) {
    const int j = packed_index(camera, p);
    if (j >= 0) terms.push_back({j, mean, sigma});
  };
  if (s.principal_point_prior) {
    add(CameraParameter::u0, pr.principal_point_px.x(), pr.principal_point_sigma_px);
    add(CameraParameter::v0, pr.principal_point_px.y(), pr.principal_point_sigma_px);
  }
  if (s.center_prior)
    for (int a = 0; a < 3; ++a) add(kCenterParameters[a], pr.center_enu_m[a], pr.center_sigma_m[a]);
  return terms;
}

ceres::Problem::Options problem_options(ceres::EvaluationCallback* callback) {
  ceres::Problem::Options po;
  po.disable_all_safety_checks = true;                        // the blocks are ours, each added once
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;  // one loss, a member of the problem's owner
  po.evaluation_callback = callback;
  return po;
}

}  // namespace

NetworkCeresProblem::NetworkCeresProblem(const NetworkLayout& layout, NetworkParameterBlocks* blocks,
                                         const NetworkSelection& selection)
    : layout_(layout),
      blocks_(blocks),
      cameras_(blocks->cameras.size()),
      problem_(std::make_unique<ceres::Problem>(problem_options(&evaluation_))),
      image_(layout.observations->size(), nullptr),
      image_single_view_(layout.observations->size(), 0),
      prior_(blocks->points.size(), {nullptr, nullptr}),
      point_constant_(blocks->points.size(), 0) {
  pack_cameras();
  for (std::size_t i = 0; i < image_.size(); ++i)
    if (selection.observation[i]) add_image_residual(i, selection);
  for (std::size_t k = 0; k < prior_.size(); ++k) {
    if (!selection.prior[k] || selection.single_view[k]) continue;
    for (int half = 0; half < 2; ++half) {
      prior_[k][static_cast<std::size_t>(half)] =
          new PointPriorCost((*layout_.points)[k].prior_enu, layout_.prior_whiten[k], half);
      problem_->AddResidualBlock(prior_[k][static_cast<std::size_t>(half)], &loss_,
                                 blocks_->points[k].data());
    }
  }
  for (std::size_t c = 0; c < cameras_.size(); ++c) {
    CameraBlock& cb = cameras_[c];
    if (cb.size == 0 || !problem_->HasParameterBlock(cb.values.data())) continue;  // no observation
    std::vector<ParameterPriorCost::Term> terms =
        camera_prior_terms(cb, layout_.setups[c], (*layout_.cameras)[c].options.priors);
    if (!terms.empty())
      problem_->AddResidualBlock(new ParameterPriorCost(cb.size, std::move(terms)), nullptr,
                                 cb.values.data());
  }
}

void NetworkCeresProblem::add_image_residual(std::size_t i, const NetworkSelection& sel) {
  const NetworkObservation& o = (*layout_.observations)[i];
  CameraBlock& cb = cameras_[o.camera];
  const NetworkPoint& p = (*layout_.points)[o.point];
  if (sel.single_view[o.point]) {  // the per-camera bundle's residual (network_parameters.hpp)
    if (cb.size == 0) return;      // a constant
    image_[i] =
        new ImageResidualCost(&cb, false, p.prior_enu, o.offset_m, o.velocity, o.pixel, sel.whitening[i]);
    image_single_view_[i] = 1;
    problem_->AddResidualBlock(image_[i], &loss_, cb.values.data());
    return;
  }
  image_[i] = new ImageResidualCost(&cb, true, p.prior_enu, o.offset_m, o.velocity, o.pixel,
                                    Eigen::Matrix2d::Identity() / layout_.pixel_sigma(i));
  image_single_view_[i] = 0;
  if (cb.size > 0)
    problem_->AddResidualBlock(image_[i], &loss_, cb.values.data(), blocks_->points[o.point].data());
  else
    problem_->AddResidualBlock(image_[i], &loss_, blocks_->points[o.point].data());
}

void NetworkCeresProblem::pack_cameras() {
  // In place: the costs hold the address of each camera's block.
  for (std::size_t c = 0; c < cameras_.size(); ++c) {
    cameras_[c] = CameraBlock::pack(layout_.setups[c], blocks_->cameras[c], layout_.starts[c]);
    cameras_[c].prepare_evaluation();
  }
}

void NetworkCeresProblem::select(const NetworkSelection& sel) {
  pack_cameras();
  for (std::size_t i = 0; i < image_.size(); ++i) {
    if (!image_[i]) continue;
    const std::size_t k = (*layout_.observations)[i].point;
    if (!sel.observation[i]) {
      image_[i]->switch_off();
    } else if (sel.single_view[k] && image_single_view_[i]) {
      image_[i]->set_whitening(sel.whitening[i]);
    } else if (sel.single_view[k]) {  // its point lost every other camera's ray
      image_[i]->switch_off();
      add_image_residual(i, sel);
    }
  }
  for (std::size_t k = 0; k < prior_.size(); ++k) {
    const bool prior_on = sel.prior[k] && !sel.single_view[k];
    if (prior_on) continue;
    for (std::size_t half = 0; half < 2; ++half)
      if (prior_[k][half]) prior_[k][half]->switch_off();
  }
  for (std::size_t k = 0; k < point_constant_.size(); ++k) {
    if (point_constant_[k] || !problem_->HasParameterBlock(blocks_->points[k].data())) continue;
    bool used = sel.prior[k] != 0;
    for (std::size_t i : layout_.by_point[k]) used = used || sel.observation[i];
    used = used && !sel.single_view[k];
    if (!used) problem_->SetParameterBlockConstant(blocks_->points[k].data()), point_constant_[k] = 1;
  }
}

int NetworkCeresProblem::solve(RobustLoss loss, double loss_scale, double tolerance, int max_iterations,
                               int num_threads) {
  loss_.Reset(new_robust_loss(loss, loss_scale), ceres::TAKE_OWNERSHIP);
  // Points first (eliminated), then the cameras; Ceres prunes the held points
  // from the ordering it is given, so each solve gets its own.
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (std::size_t k = 0; k < blocks_->points.size(); ++k)
    if (!point_constant_[k] && problem_->HasParameterBlock(blocks_->points[k].data()))
      ordering->AddElementToGroup(blocks_->points[k].data(), 0);
  for (CameraBlock& cb : cameras_)
    if (cb.size > 0 && problem_->HasParameterBlock(cb.values.data()))
      ordering->AddElementToGroup(cb.values.data(), 1);

  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_SCHUR;
  so.linear_solver_ordering = ordering;
  so.max_num_iterations = max_iterations;
  // The cameras start at the per-camera bundle's solution and the points at their PPK fixes, so the
  // Gauss–Newton step is good from the first iteration; Ceres' default initial radius (1e4, damping
  // 1e-4 of the diagonal) holds back the weakly determined f–distance direction (measured in
  // docs/performance.md, "Network bundle — solver settings").
  so.initial_trust_region_radius = 1e12;
  so.function_tolerance = tolerance;
  so.gradient_tolerance = 1e-2 * tolerance;
  so.parameter_tolerance = tolerance;
  so.num_threads = std::max(1, num_threads);
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, problem_.get(), &summary);
  if (!summary.IsSolutionUsable() || !std::isfinite(summary.final_cost))
    throw_calibration_error("network", "Levenberg–Marquardt failed: " + summary.message);
  for (std::size_t c = 0; c < cameras_.size(); ++c) {
    cameras_[c].unpack(&blocks_->cameras[c]);
    blocks_->cameras[c].rebase_rotation(layout_.starts[c]);
  }
  pack_cameras();
  return static_cast<int>(summary.iterations.size());
}

}  // namespace rangecal
