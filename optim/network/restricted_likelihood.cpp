#include "optim/network/restricted_likelihood.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>

#include "optim/estimation/jacobi_scaled_ldlt.hpp"
#include "optim/network/gauss_markov_elimination.hpp"
#include "optim/network/point_chunk.hpp"

namespace rangecal {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

LogParameters log_parameters_of(const PpkErrorModel& m, std::size_t cameras) {
  LogParameters x = LogParameters::Zero(kPpkParameters + static_cast<Eigen::Index>(cameras));
  x.head<kPpkParameters>() << std::log(m.white_scale_h), std::log(m.white_scale_v), std::log(m.gm_sd_h_m),
      std::log(m.gm_sd_v_m), std::log(m.tau_h_s), std::log(m.tau_v_s);
  return x;
}

double image_scale_of(const LogParameters& x, std::size_t c) {
  const Eigen::Index i = kPpkParameters + static_cast<Eigen::Index>(c);
  return i < x.size() ? std::exp(x[i]) : 1.0;
}

PpkErrorModel model_of(const LogParameters& x) {
  PpkErrorModel m;
  double* fields[6] = {&m.white_scale_h, &m.white_scale_v, &m.gm_sd_h_m,
                       &m.gm_sd_v_m,     &m.tau_h_s,       &m.tau_v_s};
  for (int i = 0; i < kPpkParameters; ++i) *fields[i] = std::exp(x[i]);
  return m;
}

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// Which of the six log parameters an ENU axis's white scale, GM sd and τ are.
int scale_index(int axis) {
  return axis < 2 ? 0 : 1;
}
int gm_sd_index(int axis) {
  return axis < 2 ? 2 : 3;
}
int tau_index(int axis) {
  return axis < 2 ? 4 : 5;
}

void thin_chain(NetworkLayout* l, NetworkSelection* sel, std::size_t max_states) {
  const std::size_t n = l->gm_chain.size();
  const std::size_t stride = (n + max_states - 1) / max_states;
  if (stride <= 1) return;
  std::vector<std::size_t> kept;
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t k = l->gm_chain[j];
    if (j % stride == 0) {
      l->gm_state[k] = static_cast<int>(kept.size());
      kept.push_back(k);
      continue;
    }
    l->gm_state[k] = -1;
    sel->prior[k] = 0;
    for (std::size_t i : l->by_point[k]) sel->observation[i] = 0;
  }
  l->gm_chain = std::move(kept);
}

/// The AR(1) chain's residual weights (gnss/track/ppk_error_model.hpp) per state j and axis: φ_j and
/// w_j² = 1/(σ_g²·(1 − φ_j²)) (w_0² = 1/σ_g²), and their derivatives in log τ.
struct ChainStep {
  Vector3d phi = Vector3d::Zero(), w2 = Vector3d::Zero();
  Vector3d dphi = Vector3d::Zero(), dw2 = Vector3d::Zero();  ///< ∂/∂log τ
};

std::vector<ChainStep> chain_steps(const NetworkLayout& l, const PpkErrorModel& m) {
  std::vector<ChainStep> steps(l.gm_chain.size());
  const Vector3d tau = m.tau();
  for (std::size_t j = 0; j < steps.size(); ++j) {
    ChainStep& s = steps[j];
    const double dt =
        j == 0 ? 0 : std::abs((*l.points)[l.gm_chain[j]].time_s - (*l.points)[l.gm_chain[j - 1]].time_s);
    if (j > 0) s.phi = gauss_markov_transition(m, dt);
    const Vector3d w = gauss_markov_weight(m, j > 0 ? &s.phi : nullptr);
    s.w2 = w.cwiseProduct(w);
    if (j == 0) continue;
    for (int a = 0; a < 3; ++a) {
      s.dphi[a] = s.phi[a] * dt / tau[a];
      s.dw2[a] = s.w2[a] * 2 * s.phi[a] * s.dphi[a] / std::max(1e-300, 1 - s.phi[a] * s.phi[a]);
    }
  }
  return steps;
}

/// Q⁻¹ per axis is tridiagonal: diagonal w_j² + w_{j+1}²·φ_{j+1}², below −w_j²·φ_j. With `d_tau`,
/// their derivatives in log τ instead.
Vector3d chain_diagonal(const std::vector<ChainStep>& s, std::size_t j, bool d_tau) {
  Vector3d d = d_tau ? s[j].dw2 : s[j].w2;
  if (j + 1 < s.size()) {
    const ChainStep& n = s[j + 1];
    const Vector3d phi2 = n.phi.cwiseProduct(n.phi);
    d += d_tau ? Vector3d(n.dw2.cwiseProduct(phi2) + 2 * n.w2.cwiseProduct(n.phi).cwiseProduct(n.dphi))
               : Vector3d(n.w2.cwiseProduct(phi2));
  }
  return d;
}
Vector3d chain_below(const std::vector<ChainStep>& s, std::size_t j, bool d_tau) {
  return d_tau ? Vector3d(-s[j].dw2.cwiseProduct(s[j].phi) - s[j].w2.cwiseProduct(s[j].dphi))
               : Vector3d(-s[j].w2.cwiseProduct(s[j].phi));
}

/// The normal equations of (cameras, points, states) under a model, factored as the solve
/// eliminates them: points (V_k⁻¹), states (G = L·Lᵀ, B → Z = G⁻¹·B), cameras (S, scaled LDLT).
struct Factors {
  /// The normal equations' image part under the image scales: each camera's lamp centroids
  /// (RemlMission::images) divided by s_c² and added to what no component changes.
  std::vector<PointLinearisation> lin;
  MatrixXd U;
  VectorXd gradient;
  VectorXd image_weight;  ///< 1/s_c² per camera
  std::size_t states = 0;
  std::vector<ChainStep> steps;
  std::vector<Matrix3d> Vinv, P;  ///< per point; P the fix's white information (zero without a fix)
  double chi2 = 0;                ///< χ² at the linearisation, fixes included
  GaussMarkovSystem gm;
  GaussMarkovFactor L;
  std::vector<Matrix3d> g_inverse;  ///< diagonal blocks of G⁻¹
  JacobiScaledLdlt cameras;         ///< S, the cameras' reduced system
  MatrixXd H;                       ///< factorise's workspace: a chunk of points' W·L⁻ᵀ side by side
};

/// The normal equations' image part under the scales of `x` into F (Factors::lin, U, gradient and
/// χ² at the linearisation); returns log|R| of the lamp centroids, Σ n_c·log s_c².
double scale_images(const RemlMission& f, const LogParameters& x, Factors* F) {
  const NetworkLayout& l = f.layout;
  const std::size_t nc = f.cameras();
  F->image_weight.resize(static_cast<Eigen::Index>(nc));
  F->chi2 = f.chi2;
  double log_det = 0;
  for (std::size_t c = 0; c < nc; ++c) {
    const double s = image_scale_of(x, c);
    F->image_weight[static_cast<Eigen::Index>(c)] = 1 / (s * s);
    F->chi2 += f.image_chi2[c] / (s * s);
    log_det += 2 * f.image_rows[c] * std::log(s);
  }
  F->U = f.U;
  F->gradient = f.gradient;
  for (std::size_t c = 0; c < nc; ++c) {
    const auto cols = Eigen::seqN(l.offset[c], static_cast<Eigen::Index>(l.free[c].size()));
    const double w = F->image_weight[static_cast<Eigen::Index>(c)];
    F->U(cols, cols) += w * f.image_U(cols, cols);
    F->gradient(cols) += w * f.image_gradient(cols);
  }
  F->lin.resize(f.lin.size());
  for (std::size_t k = 0; k < f.lin.size(); ++k) {
    PointLinearisation& p = F->lin[k];
    p.V = f.lin[k].V, p.grad_point = f.lin[k].grad_point, p.W = f.lin[k].W;
    for (const ImageGroup& g : f.images[k]) {
      const double w = F->image_weight[static_cast<Eigen::Index>(g.camera)];
      p.V += w * g.V, p.grad_point += w * g.grad_point;
      auto it = std::find_if(p.W.begin(), p.W.end(), [&](const auto& e) { return e.first == g.camera; });
      if (it == p.W.end())
        p.W.emplace_back(g.camera, w * g.W);
      else
        it->second += w * g.W;
    }
  }
  return log_det;
}

/// The chain's AR(1) prior into G; returns log|Q|.
double add_chain_prior(const std::vector<ChainStep>& steps, GaussMarkovSystem* gm) {
  double log_det = 0;
  for (std::size_t j = 0; j < steps.size(); ++j) {
    log_det -= steps[j].w2.array().log().sum();
    gm->diagonal[j].diagonal() += chain_diagonal(steps, j, false);
    if (j > 0) gm->below[j] = chain_below(steps, j, false);
  }
  return log_det;
}

/// Factors the normal equations at `x`; returns the log-determinants' part of D (log|R| + log|Q| +
/// log|M|), +∞ where they are not positive definite.
double factorise(const RemlMission& f, const LogParameters& x, bool chain, Factors* F) {
  const NetworkLayout& l = f.layout;
  const PpkErrorModel m = model_of(x);
  const std::size_t np = f.lin.size();
  double log_det = scale_images(f, x, F);
  F->states = chain ? l.gm_chain.size() : 0;
  const auto n3 = 3 * static_cast<Eigen::Index>(F->states);
  GaussMarkovSystem& gm = F->gm;
  gm.diagonal.assign(F->states, Matrix3d::Zero());
  gm.below.assign(F->states, Vector3d::Zero());
  gm.B.setZero(n3, l.n_camera_parameters);
  if (chain) F->steps = chain_steps(l, m), log_det += add_chain_prior(F->steps, &gm);
  MatrixXd S = F->U;
  PointChunk chunk(l.n_camera_parameters, &F->H);
  F->Vinv.assign(np, Matrix3d::Zero()), F->P.assign(np, Matrix3d::Zero());
  const Matrix3d scale = m.white_scale().asDiagonal();
  for (std::size_t k = 0; k < np; ++k) {
    if (!f.in_solve[k]) continue;
    Matrix3d V = F->lin[k].V;
    if (f.fix[k]) {  // the fix X + g + w, Cov(w) = S·Σ_pos·S (gnss/track/ppk_error_model.hpp)
      const Matrix3d white = scale * (*l.points)[k].prior_cov * scale;
      F->P[k] = white.inverse();
      log_det += std::log(white.determinant());
      V += F->P[k], F->chi2 += f.residual[k].dot(F->P[k] * f.residual[k]);
    }
    const Eigen::LLT<Matrix3d> llt(V);
    if (llt.info() != Eigen::Success) return kInfinity;
    const Matrix3d Lk = llt.matrixL();
    log_det += 2 * Lk.diagonal().array().log().sum();
    const Matrix3d LinvT = Lk.inverse().transpose();  // 3×3: closed form
    const Matrix3d& Vinv = F->Vinv[k] = LinvT * LinvT.transpose();
    // S −= W·V⁻¹·Wᵀ = (W·L⁻ᵀ)(W·L⁻ᵀ)ᵀ, V = L·Lᵀ: a chunk of points' columns side by side, one
    // product per chunk on S's lower triangle (all the eliminations and the LDLT read), as
    // network_covariance.cpp reduces the camera system.
    const Eigen::Index at = chunk.add(k);
    for (const auto& [c, W] : F->lin[k].W)
      chunk.matrix().block(l.offset[c], at, W.rows(), 3).noalias() = W * LinvT;
    if (chunk.full()) subtract_chunk_outer_product(&chunk, &S);
    if (F->states > 0 && f.fix[k])
      couple_fix_to_state(l, static_cast<std::size_t>(l.gm_state[k]), F->P[k], Vinv, F->lin[k], &gm);
  }
  subtract_chunk_outer_product(&chunk, &S);
  if (F->states > 0) {
    double log_g = 0;
    try {
      F->g_inverse = eliminate_gauss_markov(&gm, &S, nullptr, nullptr, &log_g, &F->L);
    } catch (const std::exception&) {
      return kInfinity;
    }
    log_det += log_g;
  }
  if (!F->cameras.compute(S)) return kInfinity;
  return F->cameras.add_log_determinant(log_det);
}

/// M·Δ = r solved with the factors for m right-hand sides at once: r on the cameras (r_c,
/// n_c × m), the points (r_X, 3 rows per point) and the states (r_g, 3 rows per state).
struct Solution {
  MatrixXd c, g, X;
};

auto rows3(std::size_t i) {
  return Eigen::seqN(3 * static_cast<Eigen::Index>(i), 3);
}

void solve(const RemlMission& f, const Factors& F, MatrixXd rc, const MatrixXd& rX, const MatrixXd& rg,
           Solution* s) {
  const NetworkLayout& l = f.layout;
  const Eigen::Index m = rX.cols();
  Eigen::Matrix<double, 3, Eigen::Dynamic> VrX(3, m), r(3, m);
  s->g = rg;  // reduced in place, then G⁻¹·r_g
  for (std::size_t k = 0; k < f.lin.size(); ++k) {
    if (!f.in_solve[k]) continue;
    VrX.noalias() = F.Vinv[k] * rX(rows3(k), Eigen::all);
    for (const auto& [c, W] : F.lin[k].W) rc.middleRows(l.offset[c], W.rows()).noalias() -= W * VrX;
    if (F.states > 0 && f.fix[k])
      s->g(rows3(static_cast<std::size_t>(l.gm_state[k])), Eigen::all).noalias() -= F.P[k] * VrX;
  }
  if (F.states > 0) {
    rc.noalias() -= F.gm.B.transpose() * s->g;  // B becomes Z = G⁻¹·B: Bᵀ·G⁻¹·r_g = Zᵀ·r_g
    solve_gauss_markov(F.L, &s->g);
  }
  s->c = F.cameras.solve(rc);
  if (F.states > 0) s->g.noalias() -= F.gm.B * s->c;
  s->X.setZero(rX.rows(), m);
  for (std::size_t k = 0; k < f.lin.size(); ++k) {
    if (!f.in_solve[k]) continue;
    r = rX(rows3(k), Eigen::all);
    for (const auto& [c, W] : F.lin[k].W)
      r.noalias() -= W.transpose() * s->c.middleRows(l.offset[c], W.rows());
    if (F.states > 0 && f.fix[k])
      r.noalias() -= F.P[k] * s->g(rows3(static_cast<std::size_t>(l.gm_state[k])), Eigen::all);
    s->X(rows3(k), Eigen::all).noalias() = F.Vinv[k] * r;
  }
}

/// The fitted residual of fix k (X + g − fix at the minimiser, m) from the step
/// Δ = M⁻¹·b: the minimiser is −Δ.
Vector3d fix_residual(const RemlMission& f, const Factors& F, const Solution& s, std::size_t k) {
  Vector3d e = f.residual[k] - s.X(rows3(k), 0);
  if (F.states > 0) e -= s.g(rows3(static_cast<std::size_t>(f.layout.gm_state[k])), 0);
  return e;
}

/// Σ = M⁻¹'s blocks the gradient needs: Σ_cc, T = Z·Σ_cc (Σ_gc = −T), and per state the diagonal
/// and below-diagonal blocks of Σ_gg = G⁻¹ + Z·Σ_cc·Zᵀ (gauss_markov_elimination.hpp).
struct Covariance {
  MatrixXd cc, T;
  std::vector<Matrix3d> gg, gg_below;
};

void covariance(const Factors& F, Covariance* out) {
  Covariance& C = *out;
  C.cc = F.cameras.inverse();
  if (F.states == 0) return;
  const MatrixXd& Z = F.gm.B;
  C.T.resize(Z.rows(), C.cc.cols());
  C.T.noalias() = Z * C.cc;
  const std::vector<Matrix3d> below = gauss_markov_inverse_below(F.L, F.g_inverse);
  C.gg.resize(F.states), C.gg_below.resize(F.states);
  for (std::size_t j = 0; j < F.states; ++j) {
    const auto rows = Eigen::seqN(3 * static_cast<Eigen::Index>(j), 3);
    C.gg[j] = F.g_inverse[j] + C.T(rows, Eigen::all) * Z(rows, Eigen::all).transpose();
    if (j > 0)
      C.gg_below[j] =
          below[j] + C.T(rows, Eigen::all) * Z(Eigen::seqN(rows[0] - 3, 3), Eigen::all).transpose();
  }
}

/// What the derivatives need of each point's camera columns in M⁻¹, from Y_k = Σ_cc·W_k (W_k over
/// the point's cameras), formed a chunk of points at a time as one product with Σ_cc, as factorise
/// forms the camera system: per point W_kᵀ·Σ_cc·W_k and Σ_c W_cᵀ·T_{j,c}ᵀ (its fix's state j, T =
/// Z·Σ_cc; zero without a chain); per camera tr(M⁻¹·N_c) over its lamp centroids' normal equations
/// (image_traces).
struct PointProducts {
  std::vector<Matrix3d> WSW, WT;
  VectorXd image_trace;
};

/// Cov(X_k) (m²): with u = (cameras, g_j), X_k = D·u + V_k⁻¹-noise, D = [−V_k⁻¹·W_kᵀ, −V_k⁻¹·P_k], so
/// Cov = V⁻¹ + V⁻¹·(WSW − WT·P − P·WTᵀ + P·Σ_gg,jj·P)·V⁻¹ (Σ_cg = −Tᵀ).
Matrix3d point_covariance(const RemlMission& f, const Factors& F, const Covariance& C, std::size_t k,
                          const Matrix3d& WSW, const Matrix3d& WT) {
  const Matrix3d& Vinv = F.Vinv[k];
  Matrix3d inner = WSW;
  if (F.states > 0 && f.fix[k]) {
    const Matrix3d& P = F.P[k];
    inner += -WT * P - P * WT.transpose() + P * C.gg[static_cast<std::size_t>(f.layout.gm_state[k])] * P;
  }
  return Vinv + Vinv * inner * Vinv;
}

/// Point k's share of tr(M⁻¹·N_c) for each camera c with lamp centroids of it: 2·⟨Cov(c, X_k), W_kc⟩
/// + ⟨Cov(X_k), V_kc⟩, with Cov(c, X_k) = (−Y_k,c + T_{j,c}ᵀ·P_k)·V_k⁻¹ (the camera's rows of Σ_uu·Dᵀ).
void add_image_traces(const RemlMission& f, const Factors& F, const Covariance& C, std::size_t k,
                      const Eigen::Ref<const MatrixXd>& Yk, const Matrix3d& cov, VectorXd* trace) {
  const NetworkLayout& l = f.layout;
  const bool chained = F.states > 0 && f.fix[k];
  const Eigen::Index j = chained ? 3 * static_cast<Eigen::Index>(l.gm_state[k]) : 0;
  for (const ImageGroup& g : f.images[k]) {
    const double w = F.image_weight[static_cast<Eigen::Index>(g.camera)];
    const auto rows = Eigen::seqN(l.offset[g.camera], g.W.rows());
    CameraPointBlock cross = -Yk(rows, Eigen::all);
    if (chained) cross.noalias() += C.T(Eigen::seqN(j, 3), rows).transpose() * F.P[k];
    const CameraPointBlock cam_point = cross * F.Vinv[k];
    (*trace)[static_cast<Eigen::Index>(g.camera)] +=
        w * (2 * cam_point.cwiseProduct(g.W).sum() + cov.cwiseProduct(g.V).sum());
  }
}

void point_products(const RemlMission& f, const Factors& F, const Covariance& C, MatrixXd* H, MatrixXd* Y,
                    PointProducts* out) {
  const NetworkLayout& l = f.layout;
  const std::size_t np = f.lin.size();
  out->WSW.assign(np, Matrix3d::Zero());
  out->WT.assign(np, Matrix3d::Zero());
  out->image_trace = VectorXd::Zero(static_cast<Eigen::Index>(f.cameras()));
  PointChunk chunk(l.n_camera_parameters, H);
  const auto flush = [&]() {
    if (chunk.empty()) return;
    Y->noalias() = C.cc * chunk.filled();
    for (std::size_t i = 0; i < chunk.points().size(); ++i) {
      const std::size_t k = chunk.points()[i];
      const auto Yk = Y->middleCols(3 * static_cast<Eigen::Index>(i), 3);
      for (const auto& [c, W] : F.lin[k].W) {
        out->WSW[k].noalias() += W.transpose() * Yk.middleRows(l.offset[c], W.rows());
        if (F.states > 0 && f.fix[k])
          out->WT[k].noalias() += W.transpose().lazyProduct(
              C.T.block(3 * static_cast<Eigen::Index>(l.gm_state[k]), l.offset[c], 3, W.rows()).transpose());
      }
      if (!f.images[k].empty())
        add_image_traces(f, F, C, k, Yk, point_covariance(f, F, C, k, out->WSW[k], out->WT[k]),
                         &out->image_trace);
    }
    chunk.clear();
  };
  for (std::size_t k = 0; k < np; ++k) {
    if (!f.in_solve[k] || (!f.fix[k] && f.images[k].empty())) continue;
    const Eigen::Index at = chunk.add(k);
    for (const auto& [c, W] : F.lin[k].W) chunk.matrix().block(l.offset[c], at, W.rows(), 3) = W;
    if (chunk.full()) flush();
  }
  flush();
  // The cameras' own block of N_c: tr(Σ_cc,c·U_c).
  for (std::size_t c = 0; c < f.cameras(); ++c) {
    const auto cols = Eigen::seqN(l.offset[c], static_cast<Eigen::Index>(l.free[c].size()));
    out->image_trace[static_cast<Eigen::Index>(c)] +=
        F.image_weight[static_cast<Eigen::Index>(c)] *
        C.cc(cols, cols).cwiseProduct(f.image_U(cols, cols)).sum();
  }
}

/// Cov(X_k + g_k) for fix k: with u = (cameras, g_k), X_k + g_k = D·u + V_k⁻¹-noise,
/// D = [−V_k⁻¹·W_kᵀ, I − V_k⁻¹·P_k], so Cov = V_k⁻¹ + D·Σ_uu·Dᵀ (point_products' WSW and WT).
Matrix3d fix_covariance(const RemlMission& f, const Factors& F, const Covariance& C, std::size_t k,
                        const PointProducts& pp) {
  const Matrix3d& Vinv = F.Vinv[k];
  Matrix3d cov = Vinv + Vinv * pp.WSW[k] * Vinv;
  if (F.states == 0) return cov;
  // Σ_cg = −Tᵀ: D_c·Σ_cg·D_gᵀ = V⁻¹·(Wᵀ·Tᵀ)·D_gᵀ.
  const Matrix3d Dg = Matrix3d::Identity() - Vinv * F.P[k];
  const Matrix3d cross = Vinv * pp.WT[k] * Dg.transpose();
  const auto j = static_cast<std::size_t>(f.layout.gm_state[k]);
  return cov + cross + cross.transpose() + Dg * C.gg[j] * Dg.transpose();
}

/// The minimiser −Δ (Δ = M⁻¹·b, the factors' step): ê = fix − X − g per fix (m), ĝ per state, and
/// per camera its lamp centroids' χ² there, χ²_c − 2·b_cᵀΔ + Δᵀ·N_c·Δ, with b_c and N_c its share of
/// the gradient and the normal equations; and N_c·Δ (on the camera's columns and per point).
struct Minimiser {
  std::vector<Vector3d> e_hat;
  VectorXd g_hat;
  VectorXd image_chi2;
  VectorXd camera_N_delta;                           ///< per camera, on its own columns
  std::vector<std::vector<Vector3d>> point_N_delta;  ///< per point, per ImageGroup
};

Minimiser minimiser(const RemlMission& f, const Factors& F, const Solution& s) {
  const NetworkLayout& l = f.layout;
  const std::size_t np = f.lin.size();
  Minimiser mn;
  mn.e_hat.assign(np, Vector3d::Zero());
  for (std::size_t k = 0; k < np; ++k)
    if (f.fix[k]) mn.e_hat[k] = -fix_residual(f, F, s, k);
  if (F.states > 0) mn.g_hat = -s.g.col(0);
  const VectorXd& dc = s.c.col(0);
  mn.image_chi2 = VectorXd::Zero(static_cast<Eigen::Index>(f.cameras()));
  mn.camera_N_delta = VectorXd::Zero(l.n_camera_parameters);
  mn.point_N_delta.resize(np);
  for (std::size_t c = 0; c < f.cameras(); ++c) {
    const auto cols = Eigen::seqN(l.offset[c], static_cast<Eigen::Index>(l.free[c].size()));
    const double w = F.image_weight[static_cast<Eigen::Index>(c)];
    mn.camera_N_delta(cols) = w * f.image_U(cols, cols) * dc(cols);
    mn.image_chi2[static_cast<Eigen::Index>(c)] =
        w * (f.image_chi2[c] - 2 * f.image_gradient(cols).dot(dc(cols)));
  }
  for (std::size_t k = 0; k < np; ++k) {
    mn.point_N_delta[k].clear();
    const Vector3d dX = s.X(rows3(k), 0);
    for (const ImageGroup& g : f.images[k]) {
      const double w = F.image_weight[static_cast<Eigen::Index>(g.camera)];
      const auto cols = Eigen::seqN(l.offset[g.camera], g.W.rows());
      mn.camera_N_delta(cols) += w * g.W * dX;
      mn.point_N_delta[k].push_back(w * (g.W.transpose() * dc(cols) + g.V * dX));
      mn.image_chi2[static_cast<Eigen::Index>(g.camera)] -= 2 * w * g.grad_point.dot(dX);
    }
  }
  // + Δᵀ·N_c·Δ: the camera columns' and the points' shares of N_c·Δ against Δ.
  for (std::size_t c = 0; c < f.cameras(); ++c) {
    const auto cols = Eigen::seqN(l.offset[c], static_cast<Eigen::Index>(l.free[c].size()));
    mn.image_chi2[static_cast<Eigen::Index>(c)] += mn.camera_N_delta(cols).dot(dc(cols));
  }
  for (std::size_t k = 0; k < np; ++k)
    for (std::size_t i = 0; i < f.images[k].size(); ++i)
      mn.image_chi2[static_cast<Eigen::Index>(f.images[k][i].camera)] +=
          mn.point_N_delta[k][i].dot(s.X(rows3(k), 0));
  return mn;
}

/// ∂D/∂θ (restricted_likelihood.hpp): the white scales from each fix's R, Cov(X_k + g_k) and ê_k;
/// the chain's parameters from Q⁻¹'s tridiagonal derivatives against Σ_gg + ĝ·ĝᵀ; each image scale
/// from its camera's redundancy and χ² at the minimiser.
LogParameters deviance_gradient(const RemlMission& f, const Factors& F, const Covariance& C,
                                const PointProducts& pp, const Minimiser& mn) {
  LogParameters grad = LogParameters::Zero(kPpkParameters + static_cast<Eigen::Index>(f.cameras()));
  for (std::size_t k = 0; k < f.lin.size(); ++k) {
    if (!f.fix[k]) continue;
    // ∂R⁻¹/∂log s = −(E·R⁻¹ + R⁻¹·E), E the axes the scale covers; ∂log|R|/∂log s = 2 per axis.
    const Matrix3d PC = F.P[k] * fix_covariance(f, F, C, k, pp);
    const Vector3d Pe = F.P[k] * mn.e_hat[k];
    for (int a = 0; a < 3; ++a) grad[scale_index(a)] += 2 - 2 * PC(a, a) - 2 * mn.e_hat[k][a] * Pe[a];
  }
  const auto g = [&](std::size_t j, int a) { return mn.g_hat[3 * static_cast<Eigen::Index>(j) + a]; };
  for (std::size_t j = 0; j < F.states; ++j)
    for (int a = 0; a < 3; ++a)
      for (bool d_tau : {false, true}) {
        // ∂Q⁻¹/∂log σ_g = −2·Q⁻¹; ∂log|Q|/∂log σ_g = 2 per state, ∂log|Q|/∂log τ = −Σ ∂w_j²/w_j².
        const double scale = d_tau ? 1 : -2;
        double term = scale * chain_diagonal(F.steps, j, d_tau)[a] * (C.gg[j](a, a) + g(j, a) * g(j, a));
        if (j > 0)
          term +=
              2 * scale * chain_below(F.steps, j, d_tau)[a] * (C.gg_below[j](a, a) + g(j, a) * g(j - 1, a));
        term += d_tau ? -F.steps[j].dw2[a] / F.steps[j].w2[a] : 2;
        grad[d_tau ? tau_index(a) : gm_sd_index(a)] += term;
      }
  // ∂Σ_c/∂log s_c = 2·Σ_c: 2·(n_c − tr(M⁻¹·N_c) − χ²_c,min).
  for (std::size_t c = 0; c < f.cameras(); ++c) {
    const auto i = static_cast<Eigen::Index>(c);
    grad[kPpkParameters + i] = 2 * (f.image_rows[c] - pp.image_trace[i] - mn.image_chi2[i]);
  }
  return grad;
}

/// Q·v on one axis of the chain (Q_ij = σ_g²·Π φ between them), in O(states) by a forward and a
/// backward recursion.
VectorXd chain_covariance_times(const std::vector<ChainStep>& s, int a, const VectorXd& v) {
  const auto n = static_cast<Eigen::Index>(s.size());
  VectorXd forward(n), backward = VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i)
    forward[i] = v[i] + (i > 0 ? s[static_cast<std::size_t>(i)].phi[a] * forward[i - 1] : 0);
  for (Eigen::Index i = n - 1; i-- > 0;)
    backward[i] = s[static_cast<std::size_t>(i + 1)].phi[a] * (v[i + 1] + backward[i + 1]);
  return (forward + backward) / s[0].w2[a];
}

/// The working variates wᵢ = ∂Σ/∂θ_i·P·y on the fixes (restricted_likelihood.hpp), per PPK parameter
/// and fix: Ṙ·R⁻¹·ê for a white scale (Ṙ = E·R + R·E); Q̇·Q⁻¹·ĝ = −Q·∂Q⁻¹·ĝ at the fix's state for
/// a chain parameter (2·ĝ for σ_g).
std::vector<std::vector<Vector3d>> working_variates(const RemlMission& f, const Factors& F,
                                                    const Minimiser& mn) {
  const std::size_t np = f.lin.size();
  std::vector<std::vector<Vector3d>> w(kPpkParameters, std::vector<Vector3d>(np, Vector3d::Zero()));
  for (std::size_t k = 0; k < np; ++k) {
    if (!f.fix[k]) continue;
    const Vector3d Pe = F.P[k] * mn.e_hat[k];
    const Matrix3d R = F.P[k].inverse();
    for (int i : {0, 1}) {
      const Vector3d E = i == 0 ? Vector3d(1, 1, 0) : Vector3d(0, 0, 1);
      w[static_cast<std::size_t>(i)][k] = E.cwiseProduct(mn.e_hat[k]) + R * E.cwiseProduct(Pe);
    }
  }
  if (F.states == 0) return w;
  const auto n = static_cast<Eigen::Index>(F.states);
  for (int a = 0; a < 3; ++a) {
    VectorXd g(n), v(n);
    for (Eigen::Index j = 0; j < n; ++j) g[j] = mn.g_hat[3 * j + a];
    for (Eigen::Index j = 0; j < n; ++j) {
      const auto ju = static_cast<std::size_t>(j);
      v[j] = chain_diagonal(F.steps, ju, true)[a] * g[j];
      if (j > 0) v[j] += chain_below(F.steps, ju, true)[a] * g[j - 1];
      if (j + 1 < n) v[j] += chain_below(F.steps, ju + 1, true)[a] * g[j + 1];
    }
    const VectorXd w_tau = -chain_covariance_times(F.steps, a, v);
    for (std::size_t k = 0; k < np; ++k) {
      if (!f.fix[k]) continue;
      const int j = f.layout.gm_state[k];
      w[static_cast<std::size_t>(gm_sd_index(a))][k][a] = 2 * g[j];
      w[static_cast<std::size_t>(tau_index(a))][k][a] = w_tau[j];
    }
  }
  return w;
}

/// The derivatives' buffers, kept between evaluations (as large as the step's).
struct DerivativeWorkspace {
  Covariance C;
  PointProducts pp;
  MatrixXd H, Y;  ///< point_products' chunk
  MatrixXd rc, rX, rg;
  Solution s;
};

/// AI_ij = ½·wᵢᵀ·P·wⱼ = ½·(wᵢᵀ·Σ⁻¹·wⱼ − bᵢᵀ·M⁻¹·bⱼ), bᵢ = Jᵀ·Σ⁻¹·wᵢ the variate fitted as data by the
/// same normal equations (one solve for all of them). A PPK variate's b is P·w on its fix's point
/// and state; an image variate's, with ẽ_c the camera's whitened residuals observed − fitted as the
/// fixes' ê (the linearisation's r is fitted − observed: ẽ_c = −(r_c − J_c·Δ)), −2·(b_c − N_c·Δ) on
/// its camera's columns and points, and its Σ⁻¹-norm 4·χ²_c,min (the cameras' centroids are disjoint
/// rows).
Eigen::MatrixXd average_information(const RemlMission& f, const Factors& F, const Minimiser& mn,
                                    DerivativeWorkspace* work) {
  const NetworkLayout& l = f.layout;
  const std::vector<std::vector<Vector3d>> w = working_variates(f, F, mn);
  const std::size_t np = f.lin.size();
  const auto nc = static_cast<Eigen::Index>(f.cameras());
  const Eigen::Index n = kPpkParameters + nc;
  MatrixXd& rc = work->rc;
  MatrixXd& rX = work->rX;
  MatrixXd& rg = work->rg;
  rc.setZero(l.n_camera_parameters, n);
  rX.setZero(3 * static_cast<Eigen::Index>(np), n), rg.setZero(3 * static_cast<Eigen::Index>(F.states), n);
  MatrixXd gram = MatrixXd::Zero(n, n);
  Eigen::Matrix<double, 3, kPpkParameters> W;
  for (std::size_t k = 0; k < np; ++k) {
    if (!f.fix[k]) continue;
    for (int i = 0; i < kPpkParameters; ++i) W.col(i) = w[static_cast<std::size_t>(i)][k];
    rX(rows3(k), Eigen::seqN(0, kPpkParameters)).noalias() = F.P[k] * W;
    gram.topLeftCorner<kPpkParameters, kPpkParameters>().noalias() += W.transpose() * F.P[k] * W;
    if (F.states > 0)
      rg(rows3(static_cast<std::size_t>(l.gm_state[k])), Eigen::seqN(0, kPpkParameters)) +=
          rX(rows3(k), Eigen::seqN(0, kPpkParameters));
  }
  for (std::size_t c = 0; c < f.cameras(); ++c) {
    const Eigen::Index i = kPpkParameters + static_cast<Eigen::Index>(c);
    const auto cols = Eigen::seqN(l.offset[c], static_cast<Eigen::Index>(l.free[c].size()));
    rc(cols, i) =
        -2 * (F.image_weight[i - kPpkParameters] * f.image_gradient(cols) - mn.camera_N_delta(cols));
    gram(i, i) = 4 * mn.image_chi2[i - kPpkParameters];
  }
  for (std::size_t k = 0; k < np; ++k)
    for (std::size_t g = 0; g < f.images[k].size(); ++g) {
      const ImageGroup& group = f.images[k][g];
      const double weight = F.image_weight[static_cast<Eigen::Index>(group.camera)];
      rX(rows3(k), kPpkParameters + static_cast<Eigen::Index>(group.camera)) +=
          -2 * (weight * group.grad_point - mn.point_N_delta[k][g]);
    }
  solve(f, F, rc, rX, rg, &work->s);
  const Solution& s = work->s;
  MatrixXd fitted = rc.transpose() * s.c + rX.transpose() * s.X;
  if (F.states > 0) fitted += rg.transpose() * s.g;
  const MatrixXd ai = 0.5 * (gram - fitted);
  return 0.5 * (ai + ai.transpose());
}

}  // namespace

RemlMission reml_mission(const NetworkLayout& any, const NetworkParameterBlocks& b,
                         const NetworkSelection& sel, std::size_t max_states) {
  PpkErrorModel chained;  // any correlated model: it only orders the chain
  chained.gm_sd_h_m = chained.gm_sd_v_m = 0.01, chained.tau_h_s = chained.tau_v_s = 30;
  RemlMission f;
  f.layout = make_network_layout(*any.cameras, *any.points, *any.observations, chained);
  f.layout.pixel_sigma_scale = any.pixel_sigma_scale;
  NetworkSelection images = sel;
  thin_chain(&f.layout, &images, max_states);
  const NetworkLayout& l = f.layout;
  refresh_single_view(l, b, &images);
  const std::size_t np = l.by_point.size();
  f.fix.assign(np, 0), f.in_solve.assign(np, 0), f.residual.assign(np, Vector3d::Zero());
  for (std::size_t k = 0; k < np; ++k)
    if (l.gm_state[k] >= 0 && images.prior[k]) {
      f.fix[k] = 1, images.prior[k] = 0;
      f.residual[k] = Eigen::Map<const Vector3d>(b.points[k].data()) - (*l.points)[k].prior_enu;
    }
  // The lamp centroids (observations at their camera's stated σ) of points in the solve apart, by
  // camera; the rest — pole picks at their own σ, single-view points — in lin.
  const std::vector<NetworkObservation>& obs = *l.observations;
  const auto centroid = [&](std::size_t i) {
    return images.observation[i] && obs[i].pixel_sigma_px <= 0 && !images.single_view[obs[i].point];
  };
  NetworkSelection rest = images, one = images;
  one.prior.assign(np, 0);
  one.observation.assign(obs.size(), 0);
  for (std::size_t i = 0; i < obs.size(); ++i)
    if (centroid(i)) rest.observation[i] = 0;
  const int n = l.n_camera_parameters;
  const std::size_t nc = l.setups.size();
  f.U = MatrixXd::Zero(n, n), f.gradient = VectorXd::Zero(n);
  f.image_U = MatrixXd::Zero(n, n), f.image_gradient = VectorXd::Zero(n);
  f.image_chi2.assign(nc, 0), f.image_rows.assign(nc, 0);
  int rows = 0;
  f.lin.resize(np), f.images.resize(np);
  for (std::size_t k = 0; k < np; ++k) {
    f.lin[k] = linearise_point(l, b, rest, k, &f.U, &f.chi2, &rows);
    for (const auto& [c, g] : f.lin[k].grad_camera) f.gradient.segment(l.offset[c], g.size()) += g;
    for (std::size_t c = 0; c < nc; ++c) {
      bool any_centroid = false;
      for (std::size_t i : l.by_point[k])
        if (obs[i].camera == c && centroid(i)) one.observation[i] = 1, any_centroid = true;
      if (!any_centroid) continue;
      const PointLinearisation p =
          linearise_point(l, b, one, k, &f.image_U, &f.image_chi2[c], &f.image_rows[c]);
      for (std::size_t i : l.by_point[k]) one.observation[i] = 0;
      f.image_gradient.segment(l.offset[c], p.grad_camera[0].second.size()) += p.grad_camera[0].second;
      f.images[k].push_back({c, p.V, p.W[0].second, p.grad_point});
    }
    f.in_solve[k] = f.fix[k] || !f.lin[k].V.isZero(0) || !f.images[k].empty();
  }
  add_camera_priors(l, b, &f.U, &f.chi2, &rows, &f.gradient);
  return f;
}

struct RemlFactors::State {
  Factors F;
  Solution step;    ///< Δ = M⁻¹·b
  MatrixXd bX, bg;  ///< b on the points and the states
  mutable DerivativeWorkspace work;
};

RemlFactors::RemlFactors() : state(std::make_unique<State>()) {}
RemlFactors::~RemlFactors() = default;
RemlFactors::RemlFactors(RemlFactors&&) noexcept = default;
RemlFactors& RemlFactors::operator=(RemlFactors&&) noexcept = default;

void factor_restricted_likelihood(const RemlMission& f, const LogParameters& x, bool chain,
                                  RemlFactors* out) {
  RemlFactors::State& st = *out->state;
  Factors& F = st.F;
  const double log_det = factorise(f, x, chain, &F);
  out->deviance = kInfinity;
  if (!std::isfinite(log_det)) return;
  // The step Δ = M⁻¹·b, and χ²_min = χ² − bᵀ·Δ.
  const std::size_t np = f.lin.size();
  st.bX.setZero(3 * static_cast<Eigen::Index>(np), 1);
  st.bg.setZero(3 * static_cast<Eigen::Index>(F.states), 1);
  for (std::size_t k = 0; k < np; ++k) {
    if (!f.in_solve[k]) continue;
    st.bX(rows3(k), 0) = F.lin[k].grad_point;
    if (!f.fix[k]) continue;
    const Vector3d Pe = F.P[k] * f.residual[k];
    st.bX(rows3(k), 0) += Pe;
    if (F.states > 0) st.bg(rows3(static_cast<std::size_t>(f.layout.gm_state[k])), 0) += Pe;
  }
  solve(f, F, F.gradient, st.bX, st.bg, &st.step);
  const Solution& s = st.step;
  const double decrease = F.gradient.dot(s.c.col(0)) + st.bX.col(0).dot(s.X.col(0)) +
                          (F.states > 0 ? st.bg.col(0).dot(s.g.col(0)) : 0);
  out->deviance = log_det + F.chi2 - decrease;
}

RemlEvaluation restricted_likelihood_derivatives(const RemlMission& f, const RemlFactors& factors) {
  RemlEvaluation out;
  out.deviance = factors.deviance;
  if (!std::isfinite(out.deviance)) return out;
  const Factors& F = factors.state->F;
  const Minimiser mn = minimiser(f, F, factors.state->step);
  DerivativeWorkspace& work = factors.state->work;
  covariance(F, &work.C);
  point_products(f, F, work.C, &work.H, &work.Y, &work.pp);
  out.gradient = deviance_gradient(f, F, work.C, work.pp, mn);
  out.information = average_information(f, F, mn, &work);
  for (std::size_t k : f.layout.gm_chain)
    if (f.fix[k]) out.corrections.push_back(mn.e_hat[k]);
  return out;
}

RemlEvaluation evaluate_restricted_likelihood(const RemlMission& f, const LogParameters& x, bool chain,
                                              bool derivatives) {
  RemlFactors factors;
  factor_restricted_likelihood(f, x, chain, &factors);
  if (derivatives) return restricted_likelihood_derivatives(f, factors);
  RemlEvaluation out;
  out.deviance = factors.deviance;
  return out;
}

}  // namespace rangecal
