#include "optim/network/network_covariance.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <utility>

#include "config/error.hpp"
#include "optim/bundle/projection_jacobian.hpp"
#include "optim/bundle/whitening.hpp"
#include "optim/estimation/jacobi_scaled_ldlt.hpp"
#include "optim/estimation/rank_tested_inverse.hpp"
#include "optim/estimation/symmetric_part.hpp"
#include "optim/network/gauss_markov_elimination.hpp"
#include "optim/network/point_chunk.hpp"

namespace rangecal {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

void add_camera_gradient(std::size_t c, const CameraGradient& g, PointLinearisation* pl) {
  for (auto& [camera, sum] : pl->grad_camera)
    if (camera == c) {
      sum += g;
      return;
    }
  pl->grad_camera.emplace_back(c, g);
}
/// One observation's camera columns (free order; fixed capacity, no heap).
using CameraJacobian = Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, kBundleParameterCount>;

/// Camera columns (free order) of one observation's 2 × 18 Jacobian.
CameraJacobian free_columns(const NetworkLayout& l, std::size_t camera,
                            const Eigen::Matrix<double, 2, kBundleParameterCount>& all) {
  const std::vector<CameraParameter>& fr = l.free[camera];
  CameraJacobian Jc(2, static_cast<Eigen::Index>(fr.size()));
  for (std::size_t k = 0; k < fr.size(); ++k) Jc.col(static_cast<Eigen::Index>(k)) = all.col(index_of(fr[k]));
  return Jc;
}

/// ∂uv/∂(camera, world) of observation i at the seen point X + offset − v·δ (X its point's block or,
/// for a single-view point, its prior).
ProjectionJacobian observation_jacobian(const NetworkLayout& l, const NetworkParameterBlocks& b,
                                        std::size_t i, const Eigen::Vector3d& X) {
  const NetworkObservation& o = (*l.observations)[i];
  const BundleParameterBlocks& cb = b.cameras[o.camera];
  const Camera& base = l.starts[o.camera];
  Eigen::Vector2d uv;
  ProjectionJacobian pj;
  if (!project_with_jacobian(cb.intr, cb.dist, cb.pose, cb.clock[0], cb.R0, base.intr.dx_mm, base.intr.dy_mm,
                             X + o.offset_m, o.velocity, &uv, &pj))
    throw_calibration_error("network", (o.source.empty() ? "observation " + std::to_string(i) : o.source) +
                                           " cannot be projected at the solution");
  return pj;
}

/// The bundle-style residual of observation i of a single-view point and its camera Jacobian.
void single_view_jacobian(const NetworkLayout& l, const NetworkParameterBlocks& b,
                          const NetworkSelection& sel, std::size_t i, Eigen::Vector2d* r,
                          CameraJacobian* Jc) {
  const NetworkObservation& o = (*l.observations)[i];
  const ProjectionJacobian pj = observation_jacobian(l, b, i, (*l.points)[o.point].prior_enu);
  const Eigen::Matrix<double, 2, kBundleParameterCount> all = sel.whitening[i] * pj.camera;
  *Jc = free_columns(l, o.camera, all);
  *r = sel.whitening[i] * (pj.uv - o.pixel);
}

/// Whitened residual and Jacobians of observation i: camera columns in its free order, point columns.
void image_jacobian(const NetworkLayout& l, const NetworkParameterBlocks& b, std::size_t i,
                    Eigen::Vector2d* r, CameraJacobian* Jc, Eigen::Matrix<double, 2, 3>* Jp) {
  const NetworkObservation& o = (*l.observations)[i];
  const ProjectionJacobian pj =
      observation_jacobian(l, b, i, Eigen::Map<const Eigen::Vector3d>(b.points[o.point].data()));
  const double w = 1 / l.pixel_sigma(i);
  const Eigen::Matrix<double, 2, kBundleParameterCount> all = w * pj.camera;
  *Jc = free_columns(l, o.camera, all);
  *Jp = w * pj.world;
  *r = w * (pj.uv - o.pixel);
}

/// The camera whose columns hold joint column j.
std::size_t camera_of_column(const NetworkLayout& l, int j) {
  std::size_t c = 0;
  while (c + 1 < l.offset.size() && l.offset[c + 1] <= j) ++c;
  return c;
}

std::string joint_name(const NetworkLayout& l, int j) {
  const std::size_t c = camera_of_column(l, j);
  return (*l.cameras)[c].initial.id + " " +
         parameter_name(l.free[c][static_cast<std::size_t>(j - l.offset[c])]);
}

/// The points eliminated from the normal equations: their linearisations and V_k⁻¹ (zero for a
/// point not in the solve).
struct EliminatedPoints {
  std::vector<PointLinearisation> lin;
  std::vector<Eigen::Matrix3d> Vinv;
  int count = 0;
};

/// The Gauss–Markov chain's own information (its AR(1) prior, gnss/track/ppk_error_model.hpp) into `gm`,
/// sized for `n` camera columns.
GaussMarkovSystem gauss_markov_system(const NetworkLayout& l, const NetworkParameterBlocks& b, int n,
                                      double* chi2, int* rows) {
  const std::size_t states = l.gm_chain.size();
  GaussMarkovSystem gm;
  gm.diagonal.assign(states, Eigen::Matrix3d::Zero());
  gm.below.assign(states, Eigen::Vector3d::Zero());
  gm.B = MatrixXd::Zero(3 * static_cast<Eigen::Index>(states), n);
  gm.gradient = VectorXd::Zero(3 * static_cast<Eigen::Index>(states));
  for (std::size_t j = 0; j < states; ++j) {
    const GaussMarkovStep step = gauss_markov_step(l, j);
    const Eigen::Vector3d w2 = step.weight.cwiseProduct(step.weight);
    const Eigen::Map<const Eigen::Vector3d> g(b.gm[j].data());
    gm.diagonal[j].diagonal() += w2;
    Eigen::Vector3d r = step.weight.cwiseProduct(g);
    if (j > 0) {
      gm.diagonal[j - 1].diagonal() += w2.cwiseProduct(step.phi).cwiseProduct(step.phi);
      gm.below[j] = -w2.cwiseProduct(step.phi);
      r -= step.weight.cwiseProduct(step.phi).cwiseProduct(
          Eigen::Map<const Eigen::Vector3d>(b.gm[j - 1].data()));
    }
    gm.gradient.segment<3>(3 * static_cast<Eigen::Index>(j)) += step.weight.cwiseProduct(r);
    if (j > 0)
      gm.gradient.segment<3>(3 * static_cast<Eigen::Index>(j - 1)) -=
          step.weight.cwiseProduct(step.phi).cwiseProduct(r);
    *chi2 += r.squaredNorm();
    *rows += 3;
  }
  return gm;
}

/// A chained point's coupling with its state once the point is eliminated (couple_fix_to_state), and
/// its share of the states' reduced gradient, b_g − P·V⁻¹·b_X.
void couple_state(const NetworkLayout& l, std::size_t k, const PointLinearisation& lin,
                  const Eigen::Matrix3d& Vinv, GaussMarkovSystem* gm) {
  const std::size_t j = static_cast<std::size_t>(l.gm_state[k]);
  const Eigen::Matrix3d PV = couple_fix_to_state(l, j, lin.P, Vinv, lin, gm);
  gm->gradient.segment<3>(3 * static_cast<Eigen::Index>(j)) += lin.grad_state - PV * lin.grad_point;
}

/// A point's share of the cameras' reduced gradient, b_c − W·V⁻¹·b_X (V⁻¹ zero when the point is not
/// eliminated: a single-view point's gradient is its cameras' alone).
void add_reduced_gradient(const NetworkLayout& l, const PointLinearisation& lin, const Eigen::Matrix3d& Vinv,
                          VectorXd* gradient) {
  for (const auto& [c, g] : lin.grad_camera) gradient->segment(l.offset[c], g.size()) += g;
  const Eigen::Vector3d VgX = Vinv * lin.grad_point;
  for (const auto& [c, W] : lin.W) gradient->segment(l.offset[c], W.rows()) -= W * VgX;
}

/// The reduced camera system S = U − Σ_k W_k·V_k⁻¹·W_kᵀ (both triangles) into out->S, with the
/// images' and point priors' χ² and residual count.
EliminatedPoints reduce_camera_system(const NetworkLayout& l, const NetworkParameterBlocks& b,
                                      const NetworkSelection& sel, GaussMarkovSystem* gm,
                                      NetworkCovariance* out, VectorXd* gradient = nullptr) {
  const int n = l.n_camera_parameters;
  out->S = MatrixXd::Zero(n, n);
  const std::size_t np = l.by_point.size();
  EliminatedPoints points;
  points.lin.resize(np);
  points.Vinv.assign(np, Eigen::Matrix3d::Zero());
  MatrixXd H;
  PointChunk chunk(n, &H);
  for (std::size_t k = 0; k < np; ++k) {
    points.lin[k] = linearise_point(l, b, sel, k, &out->S, &out->chi2, &out->residuals);
    const bool eliminated = !points.lin[k].V.isZero(0);
    if (eliminated) points.Vinv[k] = points.lin[k].V.inverse();
    if (gradient) add_reduced_gradient(l, points.lin[k], points.Vinv[k], gradient);
    if (!eliminated) continue;  // not in the solve
    ++points.count;
    // S −= W_k·V_k⁻¹·W_kᵀ = (W_k·L_k)(W_k·L_k)ᵀ, V_k⁻¹ = L_k·L_kᵀ: the columns W_k·L_k of a chunk
    // of points side by side (zero where a camera did not see the point), one product per chunk.
    const Eigen::Matrix3d L = points.Vinv[k].llt().matrixL();
    const Eigen::Index at = chunk.add(k);
    for (const auto& [c, W] : points.lin[k].W)
      chunk.matrix().block(l.offset[c], at, W.rows(), 3).noalias() = W * L;
    if (!points.lin[k].P.isZero(0)) couple_state(l, k, points.lin[k], points.Vinv[k], gm);
    if (chunk.full()) subtract_chunk_outer_product(&chunk, &out->S);
  }
  subtract_chunk_outer_product(&chunk, &out->S);
  out->S = out->S.selfadjointView<Eigen::Lower>();
  return points;
}

/// Σ_cc = S⁻¹ with the per-camera bundle's rank tests, each column ranged by its parameter.
void invert_camera_system(const NetworkLayout& l, double scene_distance_m, double max_speed_mps,
                          double rank_tolerance, NetworkCovariance* out) {
  const int n = l.n_camera_parameters;
  VectorXd range(n);
  std::vector<std::string> names;
  for (int j = 0; j < n; ++j) {
    const std::size_t c = camera_of_column(l, j);
    range[j] = parameter_range(l.free[c][static_cast<std::size_t>(j - l.offset[c])], l.starts[c].intr,
                               scene_distance_m, max_speed_mps);
    names.push_back(joint_name(l, j));
  }
  RankTestedInverse inverse = rank_tested_inverse(out->S, range, names, rank_tolerance);
  out->joint = std::move(inverse.covariance);
  out->rank_deficient = inverse.rank_deficient;
  out->warnings = std::move(inverse.warnings);
  out->named = std::move(inverse.named);
}

/// A single-view point's posterior given its camera: X̄ − K·e, Σ − K·J_X·Σ + K·J_θ·Σ_cc·J_θᵀ·Kᵀ
/// with K = Σ·J_Xᵀ·C⁻¹ (network_covariance.hpp).
void single_view_point_covariances(const NetworkLayout& l, const NetworkParameterBlocks& b,
                                   const NetworkSelection& sel, NetworkCovariance* out) {
  for (std::size_t k = 0; k < l.by_point.size(); ++k) {
    if (sel.single_view.empty() || !sel.single_view[k]) continue;
    for (std::size_t i : l.by_point[k]) {
      if (!sel.observation[i]) continue;
      const NetworkObservation& o = (*l.observations)[i];
      const NetworkPoint& p = (*l.points)[k];
      const Camera cam = b.cameras[o.camera].to_camera(l.starts[o.camera]);
      const Eigen::Vector3d X = network_seen_point(p.prior_enu, o, b.cameras[o.camera].clock[0]);
      Eigen::Vector2d uv;
      if (!project(cam, X, &uv)) continue;
      const Eigen::Matrix<double, 2, 3> JX = pixel_jacobian_wrt_world(cam, X);
      const double sp = l.pixel_sigma(i);
      const Eigen::Matrix3d& prior_cov = l.prior_total_cov[k];  // white: the point is not chained
      const Eigen::Matrix2d C = sp * sp * Eigen::Matrix2d::Identity() + JX * prior_cov * JX.transpose();
      const Eigen::Matrix<double, 3, 2> K = prior_cov * JX.transpose() * C.inverse();
      out->point_enu[k] = p.prior_enu - K * (uv - o.pixel);
      out->point_cov[k] = prior_cov - K * JX * prior_cov;
      if (out->joint.size() > 0) {
        Eigen::Vector2d r;
        CameraJacobian Jc;
        single_view_jacobian(l, b, sel, i, &r, &Jc);
        const MatrixXd KJ = K * sel.whitening[i].inverse() * Jc;  // ∂X/∂θ through the raw pixel Jacobian
        const int nf = static_cast<int>(Jc.cols());
        out->point_cov[k] +=
            KJ * out->joint.block(l.offset[o.camera], l.offset[o.camera], nf, nf) * KJ.transpose();
      }
    }
  }
}

/// Each eliminated point's Σ_kk = V⁻¹ + V⁻¹·Wᵀ·Σ_cc·W·V⁻¹ (cameras taken as exact when
/// rank-deficient), W_kᵀ·Σ_cc·W_k for a chunk of points at once: Σ_cc times their W_k side by side.
void eliminated_point_covariances(const NetworkLayout& l, const EliminatedPoints& points,
                                  NetworkCovariance* out) {
  MatrixXd H, SW;
  PointChunk chunk(l.n_camera_parameters, &H);
  auto finish_chunk = [&]() {
    if (chunk.empty()) return;
    if (out->joint.size() > 0) SW.noalias() = out->joint * chunk.filled();
    for (std::size_t j = 0; j < chunk.points().size(); ++j) {
      const std::size_t k = chunk.points()[j];
      Eigen::Matrix3d add = Eigen::Matrix3d::Zero();
      if (out->joint.size() > 0)
        for (const auto& [c, W] : points.lin[k].W)
          add.noalias() +=
              W.transpose() * SW.block(l.offset[c], 3 * static_cast<Eigen::Index>(j), W.rows(), 3);
      out->point_cov[k] = points.Vinv[k] + points.Vinv[k] * add * points.Vinv[k];
    }
    chunk.clear();
  };
  for (std::size_t k = 0; k < points.Vinv.size(); ++k) {
    if (points.Vinv[k].isZero(0) || !points.lin[k].P.isZero(0)) continue;  // chained: below
    const Eigen::Index at = chunk.add(k);
    for (const auto& [c, W] : points.lin[k].W) chunk.matrix().block(l.offset[c], at, W.rows(), 3) = W;
    if (chunk.full()) finish_chunk();
  }
  finish_chunk();
}

/// Each chained point's Σ_kk = V⁻¹ + V⁻¹·[Aᵀ·Σ_cc·A + P·(G⁻¹)_jj·P]·V⁻¹ with A = W − Z_jᵀ·P
/// (network_covariance.hpp); Σ_cc·A for a chunk of points at once.
void chained_point_covariances(const NetworkLayout& l, const EliminatedPoints& points, const MatrixXd& Z,
                               const std::vector<Eigen::Matrix3d>& state_cov, NetworkCovariance* out) {
  MatrixXd H, SA;
  PointChunk chunk(l.n_camera_parameters, &H);
  auto finish_chunk = [&]() {
    if (chunk.empty()) return;
    if (out->joint.size() > 0) SA.noalias() = out->joint * chunk.filled();
    for (std::size_t i = 0; i < chunk.points().size(); ++i) {
      const std::size_t k = chunk.points()[i];
      const Eigen::Index at = 3 * static_cast<Eigen::Index>(i);
      const Eigen::Matrix3d& P = points.lin[k].P;
      Eigen::Matrix3d add = P * state_cov[static_cast<std::size_t>(l.gm_state[k])] * P;
      if (out->joint.size() > 0) add.noalias() += H.middleCols(at, 3).transpose() * SA.middleCols(at, 3);
      out->point_cov[k] = points.Vinv[k] + points.Vinv[k] * add * points.Vinv[k];
    }
    chunk.clear();
  };
  for (std::size_t k = 0; k < points.Vinv.size(); ++k) {
    if (points.Vinv[k].isZero(0) || points.lin[k].P.isZero(0)) continue;
    const Eigen::Index at = chunk.add(k);
    chunk.matrix().middleCols(at, 3).noalias() =
        -Z.middleRows(3 * static_cast<Eigen::Index>(l.gm_state[k]), 3).transpose() * points.lin[k].P;
    for (const auto& [c, W] : points.lin[k].W) chunk.matrix().block(l.offset[c], at, W.rows(), 3) += W;
    if (chunk.full()) finish_chunk();
  }
  finish_chunk();
}

}  // namespace

void add_camera_priors(const NetworkLayout& l, const NetworkParameterBlocks& b, MatrixXd* U, double* chi2,
                       int* rows, VectorXd* gradient) {
  for (std::size_t c = 0; c < l.setups.size(); ++c) {
    const BundleSetup& s = l.setups[c];
    const BundlePriors& pr = (*l.cameras)[c].options.priors;
    const std::vector<CameraParameter>& fr = l.free[c];
    auto column = [&](CameraParameter p) {
      for (std::size_t k = 0; k < fr.size(); ++k)
        if (fr[k] == p) return l.offset[c] + static_cast<int>(k);
      return -1;
    };
    if (s.principal_point_prior) {
      const double sg = pr.principal_point_sigma_px;
      const double e[2] = {(b.cameras[c].intr[2] - pr.principal_point_px.x()) / sg,
                           (b.cameras[c].intr[3] - pr.principal_point_px.y()) / sg};
      const CameraParameter ps[2] = {CameraParameter::u0, CameraParameter::v0};
      for (int a = 0; a < 2; ++a) {
        const int j = column(ps[a]);
        if (j >= 0) (*U)(j, j) += 1 / (sg * sg);
        if (j >= 0 && gradient) (*gradient)[j] += e[a] / sg;
        *chi2 += e[a] * e[a];
      }
      *rows += 2;
    }
    if (s.center_prior) {
      for (int a = 0; a < 3; ++a) {
        const double sg = pr.center_sigma_m[a];
        const double e = (b.cameras[c].pose[3 + a] - pr.center_enu_m[a]) / sg;
        const int j = column(kCenterParameters[a]);
        if (j >= 0) (*U)(j, j) += 1 / (sg * sg);
        if (j >= 0 && gradient) (*gradient)[j] += e / sg;
        *chi2 += e * e;
      }
      *rows += 3;
    }
  }
}

Eigen::Matrix3d couple_fix_to_state(const NetworkLayout& l, std::size_t j, const Eigen::Matrix3d& P,
                                    const Eigen::Matrix3d& Vinv, const PointLinearisation& lin,
                                    GaussMarkovSystem* gm) {
  const Eigen::Matrix3d PV = P * Vinv;
  gm->diagonal[j] += P - PV * P;
  for (const auto& [c, W] : lin.W)
    gm->B.block(3 * static_cast<Eigen::Index>(j), l.offset[c], 3, W.rows()).noalias() -= PV * W.transpose();
  return PV;
}

PointLinearisation linearise_point(const NetworkLayout& l, const NetworkParameterBlocks& b,
                                   const NetworkSelection& sel, std::size_t k, MatrixXd* U, double* chi2,
                                   int* rows) {
  PointLinearisation pl;
  pl.W.reserve(l.starts.size());
  Eigen::Vector2d r;
  CameraJacobian Jc;
  if (!sel.single_view.empty() && sel.single_view[k]) {  // the bundle's residual: cameras only
    for (std::size_t i : l.by_point[k]) {
      if (!sel.observation[i]) continue;
      single_view_jacobian(l, b, sel, i, &r, &Jc);
      const std::size_t c = (*l.observations)[i].camera;
      add_camera_gradient(c, Jc.transpose() * r, &pl);
      if (U)
        U->block(l.offset[c], l.offset[c], Jc.cols(), Jc.cols()).noalias() += Jc.transpose().lazyProduct(Jc);
      if (chi2) *chi2 += r.squaredNorm();
      if (rows) *rows += 2;
      pl.cameras = 1;
    }
    return pl;
  }
  if (sel.prior[k]) {
    const Eigen::Matrix3d& Li = l.prior_whiten[k];
    pl.V += Li.transpose() * Li;
    Eigen::Vector3d X = Eigen::Map<const Eigen::Vector3d>(b.points[k].data());
    if (l.gm_state[k] >= 0) {  // the fix is X + g + w (gnss/track/ppk_error_model.hpp)
      pl.P = Li.transpose() * Li;
      X += Eigen::Map<const Eigen::Vector3d>(b.gm[static_cast<std::size_t>(l.gm_state[k])].data());
    }
    const Eigen::Vector3d e = Li * (X - (*l.points)[k].prior_enu);
    pl.grad_point += Li.transpose() * e;
    if (l.gm_state[k] >= 0) pl.grad_state = Li.transpose() * e;
    if (chi2) *chi2 += e.squaredNorm();
    if (rows) *rows += 3;
  }
  Eigen::Matrix<double, 2, 3> Jp;
  for (std::size_t i : l.by_point[k]) {
    if (!sel.observation[i]) continue;
    image_jacobian(l, b, i, &r, &Jc, &Jp);
    const std::size_t c = (*l.observations)[i].camera;
    pl.V += Jp.transpose() * Jp;
    pl.grad_point += Jp.transpose() * r;
    add_camera_gradient(c, Jc.transpose() * r, &pl);
    auto it = std::find_if(pl.W.begin(), pl.W.end(), [&](const auto& w) { return w.first == c; });
    if (it == pl.W.end()) {
      pl.W.emplace_back(c, CameraPointBlock::Zero(Jc.cols(), 3));
      it = pl.W.end() - 1;
    }
    it->second.noalias() += Jc.transpose().lazyProduct(Jp);
    if (U)
      U->block(l.offset[c], l.offset[c], Jc.cols(), Jc.cols()).noalias() += Jc.transpose().lazyProduct(Jc);
    if (chi2) *chi2 += r.squaredNorm();
    if (rows) *rows += 2;
  }
  pl.cameras = static_cast<int>(pl.W.size());
  return pl;
}

NetworkCovariance network_covariance(const NetworkLayout& l, const NetworkParameterBlocks& b,
                                     const NetworkSelection& sel, double scene_distance_m,
                                     double max_speed_mps, double rank_tolerance) {
  NetworkCovariance out;
  GaussMarkovSystem gm = gauss_markov_system(l, b, l.n_camera_parameters, &out.chi2, &out.residuals);
  const EliminatedPoints points = reduce_camera_system(l, b, sel, &gm, &out);
  add_camera_priors(l, b, &out.S, &out.chi2, &out.residuals);
  const std::vector<Eigen::Matrix3d> state_cov = eliminate_gauss_markov(&gm, &out.S);
  out.S = symmetric_part(out.S);
  out.parameters = l.n_camera_parameters + 3 * points.count + 3 * static_cast<int>(l.gm_chain.size());
  invert_camera_system(l, scene_distance_m, max_speed_mps, rank_tolerance, &out);

  const std::size_t np = l.by_point.size();
  out.point_cov.assign(np, Eigen::Matrix3d::Zero());
  out.point_enu.resize(np);
  for (std::size_t k = 0; k < np; ++k)
    out.point_enu[k] = Eigen::Map<const Eigen::Vector3d>(b.points[k].data());
  out.point_gm.assign(np, Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < np; ++k)
    if (l.gm_state[k] >= 0)
      out.point_gm[k] =
          Eigen::Map<const Eigen::Vector3d>(b.gm[static_cast<std::size_t>(l.gm_state[k])].data());
  single_view_point_covariances(l, b, sel, &out);
  eliminated_point_covariances(l, points, &out);
  chained_point_covariances(l, points, gm.B, state_cov, &out);
  return out;
}

double network_gauss_newton_step(const NetworkLayout& l, const NetworkParameterBlocks& b,
                                 const NetworkSelection& sel, NetworkStep* step) {
  const int n = l.n_camera_parameters;
  NetworkCovariance normal;
  GaussMarkovSystem gm = gauss_markov_system(l, b, n, &normal.chi2, &normal.residuals);
  VectorXd grad_c = VectorXd::Zero(n);
  const EliminatedPoints points = reduce_camera_system(l, b, sel, &gm, &normal, &grad_c);
  add_camera_priors(l, b, &normal.S, &normal.chi2, &normal.residuals, &grad_c);
  VectorXd state_solve = gm.gradient;  // becomes G⁻¹·b_g
  eliminate_gauss_markov(&gm, &normal.S, &state_solve, &grad_c);
  // S·δc = −b_c, Jacobi-scaled (the f–distance ridge of a narrow lens spans decades).
  JacobiScaledLdlt cameras;
  if (!cameras.compute(normal.S))
    throw_calibration_error("network", "the cameras' normal equations are not positive definite");
  const VectorXd dc = cameras.solve(-grad_c);
  const VectorXd dg = -(state_solve + gm.B * dc);  // δg = −G⁻¹·(b_g + B·δc)
  step->predicted_decrease = -grad_c.dot(dc) + gm.gradient.dot(state_solve);
  for (std::size_t k = 0; k < l.by_point.size(); ++k)
    step->predicted_decrease += points.lin[k].grad_point.dot(points.Vinv[k] * points.lin[k].grad_point);
  step->cameras.resize(l.setups.size());
  for (std::size_t c = 0; c < l.setups.size(); ++c)
    step->cameras[c] = dc.segment(l.offset[c], l.setups[c].n_free);
  step->states.assign(l.gm_chain.size(), Eigen::Vector3d::Zero());
  for (std::size_t j = 0; j < l.gm_chain.size(); ++j)
    step->states[j] = dg.segment<3>(3 * static_cast<Eigen::Index>(j));
  step->points.assign(l.by_point.size(), Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < l.by_point.size(); ++k) {
    if (points.Vinv[k].isZero(0)) continue;
    const PointLinearisation& lin = points.lin[k];
    Eigen::Vector3d rhs = lin.grad_point;  // δX = −V⁻¹·(b_X + Wᵀ·δc + P·δg)
    for (const auto& [c, W] : lin.W) rhs += W.transpose() * dc.segment(l.offset[c], W.rows());
    if (l.gm_state[k] >= 0) rhs += lin.P * step->states[static_cast<std::size_t>(l.gm_state[k])];
    step->points[k] = -points.Vinv[k] * rhs;
  }
  return normal.chi2;
}

}  // namespace rangecal
