#include "optim/network/network_parameters.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "optim/bundle/whitening.hpp"

namespace rangecal {
namespace {

/// L⁻¹ with L·Lᵀ = Σ (Σ positive definite; m⁻¹).
Eigen::Matrix3d prior_whitening(const Eigen::Matrix3d& cov) {
  const Eigen::Matrix3d L = cov.llt().matrixL();
  return L.inverse();
}

/// Indices of the observations of each point (in observation order).
std::vector<std::vector<std::size_t>> observations_by_point(std::size_t n_points,
                                                            const std::vector<NetworkObservation>& obs) {
  std::vector<std::vector<std::size_t>> by(n_points);
  for (std::size_t i = 0; i < obs.size(); ++i) by[obs[i].point].push_back(i);
  return by;
}

}  // namespace

double NetworkLayout::pixel_sigma(std::size_t i) const {
  const NetworkObservation& o = (*observations)[i];
  return pixel_sigma_scale *
         (o.pixel_sigma_px > 0 ? o.pixel_sigma_px : (*cameras)[o.camera].options.pixel_sigma_px);
}

NetworkLayout make_network_layout(const std::vector<NetworkCamera>& cameras,
                                  const std::vector<NetworkPoint>& points,
                                  const std::vector<NetworkObservation>& observations,
                                  const PpkErrorModel& ppk) {
  NetworkLayout l;
  l.cameras = &cameras, l.points = &points, l.observations = &observations;
  for (const NetworkCamera& c : cameras) {
    l.setups.push_back(bundle_setup(c.options));
    l.starts.push_back(bundle_starting_camera(c.initial, l.setups.back(), c.options));
    l.free.push_back(l.setups.back().free_parameters());
    l.offset.push_back(l.n_camera_parameters);
    l.n_camera_parameters += l.setups.back().n_free;
  }
  l.by_point = observations_by_point(points.size(), observations);
  l.ppk = ppk;
  l.gm_state.assign(points.size(), -1);
  const bool chained = ppk.correlated();
  for (std::size_t k = 0; k < points.size(); ++k)
    if (chained && !points[k].control_pole && std::isfinite(points[k].time_s)) l.gm_chain.push_back(k);
  std::stable_sort(l.gm_chain.begin(), l.gm_chain.end(),
                   [&](std::size_t a, std::size_t b) { return points[a].time_s < points[b].time_s; });
  for (std::size_t j = 0; j < l.gm_chain.size(); ++j) l.gm_state[l.gm_chain[j]] = static_cast<int>(j);
  const Eigen::Matrix3d S = ppk.white_scale().asDiagonal();
  const Eigen::Vector3d g = ppk.gm_sd();
  for (std::size_t k = 0; k < points.size(); ++k) {
    const NetworkPoint& p = points[k];
    // A pole is a survey, and a lone pair has no place in the chain: their priors are their own.
    const bool ppk_epoch = !p.control_pole && std::isfinite(p.time_s);
    const Eigen::Matrix3d white = ppk_epoch ? Eigen::Matrix3d(S * p.prior_cov * S) : p.prior_cov;
    l.prior_whiten.push_back(prior_whitening(white));
    l.prior_total_cov.push_back(l.gm_state[k] >= 0
                                    ? Eigen::Matrix3d(white + Eigen::Matrix3d(g.cwiseProduct(g).asDiagonal()))
                                    : white);
  }
  return l;
}

NetworkLayout white_approximation(const NetworkLayout& layout) {
  NetworkLayout white = layout;
  white.gm_chain.clear();
  white.gm_state.assign(layout.gm_state.size(), -1);
  for (std::size_t k = 0; k < white.prior_whiten.size(); ++k)
    white.prior_whiten[k] = prior_whitening(layout.prior_total_cov[k]);
  return white;
}

GaussMarkovStep gauss_markov_step(const NetworkLayout& l, std::size_t j) {
  GaussMarkovStep step;
  if (j == 0) {
    step.weight = gauss_markov_weight(l.ppk, nullptr);
    return step;
  }
  const double dt = (*l.points)[l.gm_chain[j]].time_s - (*l.points)[l.gm_chain[j - 1]].time_s;
  step.phi = gauss_markov_transition(l.ppk, dt);
  step.weight = gauss_markov_weight(l.ppk, &step.phi);
  return step;
}

NetworkParameterBlocks starting_blocks(const NetworkLayout& l) {
  NetworkParameterBlocks b;
  for (std::size_t c = 0; c < l.starts.size(); ++c)
    b.cameras.push_back(
        BundleParameterBlocks::from_camera(l.starts[c], (*l.cameras)[c].options.initial_clock_offset_s));
  for (const NetworkPoint& p : *l.points)
    b.points.push_back({p.prior_enu.x(), p.prior_enu.y(), p.prior_enu.z()});
  b.gm.assign(l.gm_chain.size(), {0.0, 0.0, 0.0});
  return b;
}

void refresh_single_view(const NetworkLayout& l, const NetworkParameterBlocks& b, NetworkSelection* sel) {
  const std::vector<NetworkObservation>& obs = *l.observations;
  sel->single_view.assign(l.by_point.size(), 0);
  sel->whitening.assign(obs.size(), Eigen::Matrix2d::Zero());
  std::vector<Camera> cams;
  for (std::size_t c = 0; c < b.cameras.size(); ++c) cams.push_back(b.cameras[c].to_camera(l.starts[c]));
  for (std::size_t k = 0; k < l.by_point.size(); ++k) {
    if (!sel->prior[k] || l.gm_state[k] >= 0) continue;
    std::size_t used = 0, last = 0;
    for (std::size_t i : l.by_point[k])
      if (sel->observation[i]) ++used, last = i;
    if (used != 1) continue;
    sel->single_view[k] = 1;
    const NetworkObservation& o = obs[last];
    BundleObservation bo;
    bo.world = (*l.points)[k].prior_enu + o.offset_m;
    bo.world_cov = l.prior_total_cov[k];
    sel->whitening[last] = whitening_matrix(cams[o.camera], bo, l.pixel_sigma(last));
  }
}

}  // namespace rangecal
