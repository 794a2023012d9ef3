#include "optim/network/restricted_likelihood.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>

#include "optim/network/gauss_markov_elimination.hpp"

namespace rangecal {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

LogParameters log_parameters_of(const PpkErrorModel& m) {
  LogParameters x;
  x << std::log(m.white_scale_h), std::log(m.white_scale_v), std::log(m.gm_sd_h_m), std::log(m.gm_sd_v_m),
      std::log(m.tau_h_s), std::log(m.tau_v_s);
  return x;
}

PpkErrorModel model_of(const LogParameters& x) {
  PpkErrorModel m;
  double* fields[6] = {&m.white_scale_h, &m.white_scale_v, &m.gm_sd_h_m,
                       &m.gm_sd_v_m,     &m.tau_h_s,       &m.tau_v_s};
  for (int i = 0; i < 6; ++i) *fields[i] = std::exp(x[i]);
  return m;
}

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
/// Points whose camera–camera products are made as one (factorise).
constexpr int kChunk = 256;

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

/// The AR(1) chain's residual weights (ppk_error_model.hpp) per state j and axis: φ_j and
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
  std::size_t states = 0;
  std::vector<ChainStep> steps;
  std::vector<Matrix3d> Vinv, P;  ///< per point; P the fix's white information (zero without a fix)
  double chi2 = 0;                ///< χ² at the linearisation, fixes included
  GaussMarkovSystem gm;
  GaussMarkovFactor L;
  std::vector<Matrix3d> g_inverse;  ///< diagonal blocks of G⁻¹
  VectorXd d;                       ///< S's scaling: S = d⁻¹·(LDLᵀ)·d⁻¹
  Eigen::LDLT<MatrixXd> ldlt;
  MatrixXd H;  ///< factorise's workspace: a chunk of points' W·L⁻ᵀ side by side
};

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

/// Factors the normal equations of `m`; returns the log-determinants' part of D (log|R| + log|Q| +
/// log|M|), +∞ where they are not positive definite.
double factorise(const RemlMission& f, const PpkErrorModel& m, bool chain, Factors* F) {
  const NetworkLayout& l = f.layout;
  const std::size_t np = f.lin.size();
  F->states = chain ? l.gm_chain.size() : 0;
  const auto n3 = 3 * static_cast<Eigen::Index>(F->states);
  GaussMarkovSystem& gm = F->gm;
  gm.diagonal.assign(F->states, Matrix3d::Zero());
  gm.below.assign(F->states, Vector3d::Zero());
  gm.B.setZero(n3, l.n_camera_parameters);
  double log_det = 0;
  if (chain) F->steps = chain_steps(l, m), log_det += add_chain_prior(F->steps, &gm);
  MatrixXd S = f.U;
  MatrixXd& H = F->H;
  H.setZero(l.n_camera_parameters, 3 * kChunk);
  int filled = 0;
  const auto flush = [&]() {
    if (filled == 0) return;
    S.selfadjointView<Eigen::Lower>().rankUpdate(H.leftCols(3 * filled), -1.0);
    H.leftCols(3 * filled).setZero();
    filled = 0;
  };
  F->chi2 = f.chi2;
  F->Vinv.assign(np, Matrix3d::Zero()), F->P.assign(np, Matrix3d::Zero());
  const Matrix3d scale = m.white_scale().asDiagonal();
  for (std::size_t k = 0; k < np; ++k) {
    if (!f.in_solve[k]) continue;
    Matrix3d V = f.lin[k].V;
    if (f.fix[k]) {  // the fix X + g + w, Cov(w) = S·Σ_pos·S (ppk_error_model.hpp)
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
    for (const auto& [c, W] : f.lin[k].W) H.block(l.offset[c], 3 * filled, W.rows(), 3).noalias() = W * LinvT;
    if (++filled == kChunk) flush();
    if (F->states > 0 && f.fix[k])
      couple_fix_to_state(l, static_cast<std::size_t>(l.gm_state[k]), F->P[k], Vinv, f.lin[k], &gm);
  }
  flush();
  if (F->states > 0) {
    double log_g = 0;
    try {
      F->g_inverse = eliminate_gauss_markov(&gm, &S, nullptr, nullptr, &log_g, &F->L);
    } catch (const std::exception&) {
      return kInfinity;
    }
    log_det += log_g;
  }
  F->d = S.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  F->ldlt.compute(F->d.asDiagonal() * S * F->d.asDiagonal());
  if (F->ldlt.info() != Eigen::Success || !(F->ldlt.vectorD().array() > 0).all()) return kInfinity;
  return log_det + F->ldlt.vectorD().array().log().sum() - 2 * F->d.array().log().sum();
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
    for (const auto& [c, W] : f.lin[k].W) rc.middleRows(l.offset[c], W.rows()).noalias() -= W * VrX;
    if (F.states > 0 && f.fix[k])
      s->g(rows3(static_cast<std::size_t>(l.gm_state[k])), Eigen::all).noalias() -= F.P[k] * VrX;
  }
  if (F.states > 0) {
    rc.noalias() -= F.gm.B.transpose() * s->g;  // B becomes Z = G⁻¹·B: Bᵀ·G⁻¹·r_g = Zᵀ·r_g
    solve_gauss_markov(F.L, &s->g);
  }
  s->c = F.d.asDiagonal() * F.ldlt.solve(F.d.asDiagonal() * rc);
  if (F.states > 0) s->g.noalias() -= F.gm.B * s->c;
  s->X.setZero(rX.rows(), m);
  for (std::size_t k = 0; k < f.lin.size(); ++k) {
    if (!f.in_solve[k]) continue;
    r = rX(rows3(k), Eigen::all);
    for (const auto& [c, W] : f.lin[k].W)
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
  C.cc = F.d.asDiagonal() * F.ldlt.solve(MatrixXd(F.d.asDiagonal()));
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

/// W_kᵀ·Σ_cc·W_k per point in the solve (3×3), a chunk of points at a time: their W side by side
/// (zero where a camera did not see the point), multiplied by Σ_cc as one product, as factorise
/// forms the camera system.
void projected_camera_covariances(const RemlMission& f, const Covariance& C, MatrixXd* H, MatrixXd* Y,
                                  std::vector<Matrix3d>* out) {
  const NetworkLayout& l = f.layout;
  out->assign(f.lin.size(), Matrix3d::Zero());
  H->setZero(l.n_camera_parameters, 3 * kChunk);
  std::vector<std::size_t> chunk;
  const auto flush = [&]() {
    if (chunk.empty()) return;
    const Eigen::Index cols = 3 * static_cast<Eigen::Index>(chunk.size());
    Y->noalias() = C.cc * H->leftCols(cols);
    for (std::size_t i = 0; i < chunk.size(); ++i) {
      const Eigen::Index at = 3 * static_cast<Eigen::Index>(i);
      for (const auto& [c, W] : f.lin[chunk[i]].W)
        (*out)[chunk[i]].noalias() += W.transpose() * Y->block(l.offset[c], at, W.rows(), 3);
    }
    H->leftCols(cols).setZero();
    chunk.clear();
  };
  for (std::size_t k = 0; k < f.lin.size(); ++k) {
    if (!f.fix[k]) continue;
    const Eigen::Index at = 3 * static_cast<Eigen::Index>(chunk.size());
    for (const auto& [c, W] : f.lin[k].W) H->block(l.offset[c], at, W.rows(), 3) = W;
    chunk.push_back(k);
    if (chunk.size() == static_cast<std::size_t>(kChunk)) flush();
  }
  flush();
}

/// Cov(X_k + g_k) for fix k: with u = (cameras, g_k), X_k + g_k = D·u + V_k⁻¹-noise,
/// D = [−V_k⁻¹·W_kᵀ, I − V_k⁻¹·P_k], so Cov = V_k⁻¹ + D·Σ_uu·Dᵀ; `WSW` = W_kᵀ·Σ_cc·W_k
/// (projected_camera_covariances).
Matrix3d fix_covariance(const RemlMission& f, const Factors& F, const Covariance& C, std::size_t k,
                        const Matrix3d& WSW) {
  const NetworkLayout& l = f.layout;
  const Matrix3d& Vinv = F.Vinv[k];
  Matrix3d cov = Vinv + Vinv * WSW * Vinv;
  if (F.states == 0) return cov;
  const Eigen::Index j = 3 * static_cast<Eigen::Index>(l.gm_state[k]);
  Matrix3d WT = Matrix3d::Zero();  // Σ Wᵀ·Tᵀ (T = Z·Σ_cc)
  for (const auto& [c, W] : f.lin[k].W)
    WT.noalias() += W.transpose().lazyProduct(C.T.block(j, l.offset[c], 3, W.rows()).transpose());
  // Σ_cg = −Tᵀ: D_c·Σ_cg·D_gᵀ = V⁻¹·(Wᵀ·Tᵀ)·D_gᵀ.
  const Matrix3d Dg = Matrix3d::Identity() - Vinv * F.P[k];
  const Matrix3d cross = Vinv * WT * Dg.transpose();
  return cov + cross + cross.transpose() + Dg * C.gg[static_cast<std::size_t>(j / 3)] * Dg.transpose();
}

/// The model's effect on the fixes and the states at the minimiser: ê = fix − X − g per fix (m) and
/// ĝ per state.
struct Minimiser {
  std::vector<Vector3d> e_hat;
  VectorXd g_hat;
};

/// ∂D/∂θ (restricted_likelihood.hpp): the white scales from each fix's R, Cov(X_k + g_k) and ê_k;
/// the chain's parameters from Q⁻¹'s tridiagonal derivatives against Σ_gg + ĝ·ĝᵀ.
LogParameters deviance_gradient(const RemlMission& f, const Factors& F, const Covariance& C,
                                const std::vector<Matrix3d>& WSW, const Minimiser& mn) {
  LogParameters grad = LogParameters::Zero();
  for (std::size_t k = 0; k < f.lin.size(); ++k) {
    if (!f.fix[k]) continue;
    // ∂R⁻¹/∂log s = −(E·R⁻¹ + R⁻¹·E), E the axes the scale covers; ∂log|R|/∂log s = 2 per axis.
    const Matrix3d PC = F.P[k] * fix_covariance(f, F, C, k, WSW[k]);
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

/// The working variates wᵢ = ∂Σ/∂θ_i·P·y on the fixes (restricted_likelihood.hpp), per parameter
/// and fix: Ṙ·R⁻¹·ê for a white scale (Ṙ = E·R + R·E); Q̇·Q⁻¹·ĝ = −Q·∂Q⁻¹·ĝ at the fix's state for
/// a chain parameter (2·ĝ for σ_g).
std::vector<std::vector<Vector3d>> working_variates(const RemlMission& f, const Factors& F,
                                                    const Minimiser& mn) {
  const std::size_t np = f.lin.size();
  std::vector<std::vector<Vector3d>> w(6, std::vector<Vector3d>(np, Vector3d::Zero()));
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
  std::vector<Matrix3d> WSW;  ///< W_kᵀ·Σ_cc·W_k per point
  MatrixXd H, Y;              ///< projected_camera_covariances' chunk
  MatrixXd rX, rg;
  Solution s;
};

/// AI_ij = ½·wᵢᵀ·P·wⱼ: P·wⱼ on the fixes is R⁻¹ times wⱼ's residual when wⱼ is fitted as data by
/// the same normal equations (one solve for all of them).
Eigen::Matrix<double, 6, 6> average_information(const RemlMission& f, const Factors& F, const Minimiser& mn,
                                                DerivativeWorkspace* work) {
  const std::vector<std::vector<Vector3d>> w = working_variates(f, F, mn);
  const std::size_t np = f.lin.size();
  const int n = F.states > 0 ? 6 : 2;
  MatrixXd& rX = work->rX;
  MatrixXd& rg = work->rg;
  rX.setZero(3 * static_cast<Eigen::Index>(np), n), rg.setZero(3 * static_cast<Eigen::Index>(F.states), n);
  for (std::size_t k = 0; k < np; ++k) {
    if (!f.fix[k]) continue;
    for (int i = 0; i < n; ++i) rX(rows3(k), i) = F.P[k] * w[static_cast<std::size_t>(i)][k];
    if (F.states > 0)
      rg(rows3(static_cast<std::size_t>(f.layout.gm_state[k])), Eigen::all) += rX(rows3(k), Eigen::all);
  }
  solve(f, F, MatrixXd::Zero(f.layout.n_camera_parameters, n), rX, rg, &work->s);
  const Solution& s = work->s;
  Eigen::Matrix<double, 6, 6> ai = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 3, Eigen::Dynamic> W(3, n), fitted(3, n);
  for (std::size_t k = 0; k < np; ++k) {
    if (!f.fix[k]) continue;
    for (int i = 0; i < n; ++i) W.col(i) = w[static_cast<std::size_t>(i)][k];
    fitted = s.X(rows3(k), Eigen::all);
    if (F.states > 0) fitted += s.g(rows3(static_cast<std::size_t>(f.layout.gm_state[k])), Eigen::all);
    ai.topLeftCorner(n, n).noalias() += 0.5 * W.transpose() * F.P[k] * (W - fitted);
  }
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
  const int n = l.n_camera_parameters;
  f.U = MatrixXd::Zero(n, n), f.gradient = VectorXd::Zero(n);
  int rows = 0;
  f.lin.resize(np);
  for (std::size_t k = 0; k < np; ++k) {
    f.lin[k] = linearise_point(l, b, images, k, &f.U, &f.chi2, &rows);
    for (const auto& [c, g] : f.lin[k].grad_camera) f.gradient.segment(l.offset[c], g.size()) += g;
    f.in_solve[k] = f.fix[k] || !f.lin[k].V.isZero(0);
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

void factor_restricted_likelihood(const RemlMission& f, const PpkErrorModel& m, bool chain,
                                  RemlFactors* out) {
  RemlFactors::State& st = *out->state;
  Factors& F = st.F;
  const double log_det = factorise(f, m, chain, &F);
  out->deviance = kInfinity;
  if (!std::isfinite(log_det)) return;
  // The step Δ = M⁻¹·b, and χ²_min = χ² − bᵀ·Δ.
  const std::size_t np = f.lin.size();
  st.bX.setZero(3 * static_cast<Eigen::Index>(np), 1);
  st.bg.setZero(3 * static_cast<Eigen::Index>(F.states), 1);
  for (std::size_t k = 0; k < np; ++k) {
    if (!f.in_solve[k]) continue;
    st.bX(rows3(k), 0) = f.lin[k].grad_point;
    if (!f.fix[k]) continue;
    const Vector3d Pe = F.P[k] * f.residual[k];
    st.bX(rows3(k), 0) += Pe;
    if (F.states > 0) st.bg(rows3(static_cast<std::size_t>(f.layout.gm_state[k])), 0) += Pe;
  }
  solve(f, F, f.gradient, st.bX, st.bg, &st.step);
  const Solution& s = st.step;
  const double decrease = f.gradient.dot(s.c.col(0)) + st.bX.col(0).dot(s.X.col(0)) +
                          (F.states > 0 ? st.bg.col(0).dot(s.g.col(0)) : 0);
  out->deviance = log_det + F.chi2 - decrease;
}

RemlEvaluation restricted_likelihood_derivatives(const RemlMission& f, const RemlFactors& factors) {
  RemlEvaluation out;
  out.deviance = factors.deviance;
  if (!std::isfinite(out.deviance)) return out;
  const Factors& F = factors.state->F;
  const Solution& s = factors.state->step;
  const std::size_t np = f.lin.size();
  Minimiser mn;
  mn.e_hat.assign(np, Vector3d::Zero());
  for (std::size_t k = 0; k < np; ++k)
    if (f.fix[k]) mn.e_hat[k] = -fix_residual(f, F, s, k);
  if (F.states > 0) mn.g_hat = -s.g.col(0);
  DerivativeWorkspace& work = factors.state->work;
  covariance(F, &work.C);
  projected_camera_covariances(f, work.C, &work.H, &work.Y, &work.WSW);
  out.gradient = deviance_gradient(f, F, work.C, work.WSW, mn);
  out.information = average_information(f, F, mn, &work);
  for (std::size_t k : f.layout.gm_chain)
    if (f.fix[k]) out.corrections.push_back(mn.e_hat[k]);
  return out;
}

RemlEvaluation evaluate_restricted_likelihood(const RemlMission& f, const PpkErrorModel& m, bool chain,
                                              bool derivatives) {
  RemlFactors factors;
  factor_restricted_likelihood(f, m, chain, &factors);
  if (derivatives) return restricted_likelihood_derivatives(f, factors);
  RemlEvaluation out;
  out.deviance = factors.deviance;
  return out;
}

}  // namespace rangecal
