#include "optim/network/network_covariance.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>

#include "config/error.hpp"
#include "optim/bundle/projection_jacobian.hpp"
#include "optim/bundle/whitening.hpp"

namespace rangecal {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
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

/// The camera priors' information and χ² (principal point, centre), as the per-camera bundle's.
void add_camera_priors(const NetworkLayout& l, const NetworkParameterBlocks& b, MatrixXd* U, double* chi2,
                       int* rows) {
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
        *chi2 += e * e;
      }
      *rows += 3;
    }
  }
}

std::string joint_name(const NetworkLayout& l, int j) {
  std::size_t c = 0;
  while (c + 1 < l.offset.size() && l.offset[c + 1] <= j) ++c;
  return (*l.cameras)[c].initial.id + " " +
         parameter_name(l.free[c][static_cast<std::size_t>(j - l.offset[c])]);
}

}  // namespace

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
    const Eigen::Vector3d e =
        Li * (Eigen::Map<const Eigen::Vector3d>(b.points[k].data()) - (*l.points)[k].prior_enu);
    if (chi2) *chi2 += e.squaredNorm();
    if (rows) *rows += 3;
  }
  Eigen::Matrix<double, 2, 3> Jp;
  for (std::size_t i : l.by_point[k]) {
    if (!sel.observation[i]) continue;
    image_jacobian(l, b, i, &r, &Jc, &Jp);
    const std::size_t c = (*l.observations)[i].camera;
    pl.V += Jp.transpose() * Jp;
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
  const int n = l.n_camera_parameters;
  out.S = MatrixXd::Zero(n, n);
  const std::size_t np = l.by_point.size();
  std::vector<PointLinearisation> lin(np);
  std::vector<Eigen::Matrix3d> Vinv(np, Eigen::Matrix3d::Zero());
  int n_points = 0;
  constexpr int kChunk = 256;
  MatrixXd H = MatrixXd::Zero(n, 3 * kChunk);
  int filled = 0;
  auto flush = [&]() {
    if (filled == 0) return;
    out.S.selfadjointView<Eigen::Lower>().rankUpdate(H.leftCols(3 * filled), -1.0);
    H.leftCols(3 * filled).setZero();
    filled = 0;
  };
  for (std::size_t k = 0; k < np; ++k) {
    lin[k] = linearise_point(l, b, sel, k, &out.S, &out.chi2, &out.residuals);
    if (lin[k].V.isZero(0)) continue;  // not in the solve
    ++n_points;
    Vinv[k] = lin[k].V.inverse();
    // S −= W_k·V_k⁻¹·W_kᵀ = (W_k·L_k)(W_k·L_k)ᵀ, V_k⁻¹ = L_k·L_kᵀ: the columns W_k·L_k of a chunk
    // of points side by side (zero where a camera did not see the point), one product per chunk.
    const Eigen::Matrix3d L = Vinv[k].llt().matrixL();
    for (const auto& [c, W] : lin[k].W) H.block(l.offset[c], 3 * filled, W.rows(), 3).noalias() = W * L;
    if (++filled == kChunk) flush();
  }
  flush();
  out.S = out.S.selfadjointView<Eigen::Lower>();
  add_camera_priors(l, b, &out.S, &out.chi2, &out.residuals);
  out.S = 0.5 * (out.S + out.S.transpose()).eval();
  out.parameters = n + 3 * n_points;

  // Rank tests (as the per-camera bundle): Jacobi-scaled, and scaled by each parameter's range.
  VectorXd js(n), ps(n);
  std::string undetermined;
  for (int j = 0; j < n; ++j) {
    js[j] = out.S(j, j) > 0 ? 1 / std::sqrt(out.S(j, j)) : 0;
    if (!(out.S(j, j) > 0)) undetermined += (undetermined.empty() ? "" : ", ") + joint_name(l, j);
    std::size_t c = 0;
    while (c + 1 < l.offset.size() && l.offset[c + 1] <= j) ++c;
    ps[j] = parameter_range(l.free[c][static_cast<std::size_t>(j - l.offset[c])], l.starts[c].intr,
                            scene_distance_m, max_speed_mps);
  }
  if (!undetermined.empty()) {
    out.rank_deficient = true;
    out.warnings.push_back("covariance is rank-deficient: the data do not depend on " + undetermined +
                           " at all (fix it or add observations that do)");
  } else if (n > 0) {
    const Eigen::SelfAdjointEigenSolver<MatrixXd> et(ps.asDiagonal() * out.S * ps.asDiagonal());
    const Eigen::SelfAdjointEigenSolver<MatrixXd> es(js.asDiagonal() * out.S * js.asDiagonal());
    const VectorXd lt = et.eigenvalues(), lam = es.eigenvalues();
    const bool physical_ok = lt[0] > rank_tolerance * lt[n - 1];
    if (!physical_ok || !(lam[0] > rank_tolerance * lam[n - 1])) {
      out.rank_deficient = true;
      const VectorXd nullv =
          !physical_ok ? VectorXd(et.eigenvectors().col(0)) : VectorXd(es.eigenvectors().col(0));
      std::string list;
      for (int j = 0; j < n; ++j)
        if (std::abs(nullv[j]) > 0.2) list += (list.empty() ? "" : ", ") + joint_name(l, j);
      out.warnings.push_back("covariance is rank-deficient: " + list +
                             " cannot be determined from these data; fix some of them or add a prior");
    } else {
      const MatrixXd inv =
          es.eigenvectors() * lam.cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
      out.joint = js.asDiagonal() * inv * js.asDiagonal();
    }
  }

  // Each point: Σ_kk = V⁻¹ + V⁻¹·Wᵀ·Σ_cc·W·V⁻¹ (cameras taken as exact when rank-deficient).
  out.point_cov.assign(np, Eigen::Matrix3d::Zero());
  out.point_enu.resize(np);
  for (std::size_t k = 0; k < np; ++k)
    out.point_enu[k] = Eigen::Map<const Eigen::Vector3d>(b.points[k].data());
  for (std::size_t k = 0; k < np; ++k) {
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
      const Eigen::Matrix2d C = sp * sp * Eigen::Matrix2d::Identity() + JX * p.prior_cov * JX.transpose();
      const Eigen::Matrix<double, 3, 2> K = p.prior_cov * JX.transpose() * C.inverse();
      out.point_enu[k] = p.prior_enu - K * (uv - o.pixel);
      out.point_cov[k] = p.prior_cov - K * JX * p.prior_cov;
      if (out.joint.size() > 0) {
        Eigen::Vector2d r;
        CameraJacobian Jc;
        single_view_jacobian(l, b, sel, i, &r, &Jc);
        const MatrixXd KJ = K * sel.whitening[i].inverse() * Jc;  // ∂X/∂θ through the raw pixel Jacobian
        const int nf = static_cast<int>(Jc.cols());
        out.point_cov[k] +=
            KJ * out.joint.block(l.offset[o.camera], l.offset[o.camera], nf, nf) * KJ.transpose();
      }
    }
  }
  // W_kᵀ·Σ_cc·W_k for a chunk of points at once: Σ_cc times their W_k side by side.
  std::vector<std::size_t> chunk;
  MatrixXd SW;
  auto finish_chunk = [&]() {
    if (out.joint.size() > 0 && !chunk.empty()) SW.noalias() = out.joint * H.leftCols(3 * filled);
    for (std::size_t j = 0; j < chunk.size(); ++j) {
      const std::size_t k = chunk[j];
      Eigen::Matrix3d add = Eigen::Matrix3d::Zero();
      if (out.joint.size() > 0)
        for (const auto& [c, W] : lin[k].W)
          add.noalias() +=
              W.transpose() * SW.block(l.offset[c], 3 * static_cast<Eigen::Index>(j), W.rows(), 3);
      out.point_cov[k] = Vinv[k] + Vinv[k] * add * Vinv[k];
    }
    H.leftCols(3 * filled).setZero();
    filled = 0;
    chunk.clear();
  };
  for (std::size_t k = 0; k < np; ++k) {
    if (Vinv[k].isZero(0)) continue;
    for (const auto& [c, W] : lin[k].W) H.block(l.offset[c], 3 * filled, W.rows(), 3) = W;
    chunk.push_back(k);
    if (++filled == kChunk) finish_chunk();
  }
  finish_chunk();
  return out;
}

}  // namespace rangecal
