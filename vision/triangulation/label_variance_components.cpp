#include "vision/triangulation/label_variance_components.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "config/chi2_quantile.hpp"

namespace rangecal {

namespace {

// Which component scales each camera's label variance. A label interpolated at weight w between two
// frames whose labels err alike (correlation ρ) has variance σ²·((1 − w)² + w² + 2ρ·w(1 − w)): the
// part at the frames (`at_frame`, θ_a) and the part between them (`between`, θ_b = ρ·θ_a) are
// separate components when the labels' correlation is estimated, one when it is not (ρ = 1: the σ
// whole at any w); −1: held as given.
struct Grouping {
  std::vector<int> at_frame, between;
};

// A view's label variance as (component, coefficient) terms: σ²·((1 − w)² + w²) and σ²·2w(1 − w).
std::array<std::pair<int, double>, 2> label_terms(const LabelVcView& v, const Grouping& g) {
  const double w = v.interpolation_weight, var = v.label_sigma_px * v.label_sigma_px;
  return {{{g.at_frame[v.camera], var * ((1 - w) * (1 - w) + w * w)},
           {g.between[v.camera], var * 2 * w * (1 - w)}}};
}

double label_variance(const LabelVcView& v, const Grouping& g, const std::vector<double>& theta) {
  double out = 0;
  for (const auto& [k, coefficient] : label_terms(v, g))
    out += (k >= 0 ? theta[static_cast<std::size_t>(k)] : 1.0) * coefficient;
  return out;
}

// An instant's data that do not change with the scales: its views' point and calibration Jacobians,
// the latter over the instant's own columns of u.
struct VcInstantData {
  const LabelVcInstant* views = nullptr;
  Eigen::MatrixXd A;                  // 2m×3
  Eigen::VectorXd r;                  // 2m
  Eigen::MatrixXd B;                  // 2m×q_i
  std::vector<Eigen::Index> columns;  // local column → u's entry
  int dof = 0;
};

std::vector<VcInstantData> prepare(const std::vector<LabelVcInstant>& instants) {
  std::vector<VcInstantData> out;
  for (const LabelVcInstant& inst : instants) {
    const auto m = static_cast<Eigen::Index>(inst.size());
    if (2 * m - 3 < 1) continue;
    VcInstantData d;
    d.views = &inst;
    d.dof = static_cast<int>(2 * m - 3);
    for (const LabelVcView& v : inst)
      for (Eigen::Index j = 0; j < v.d_pixel_d_common.cols(); ++j) d.columns.push_back(v.common_offset + j);
    std::sort(d.columns.begin(), d.columns.end());
    d.columns.erase(std::unique(d.columns.begin(), d.columns.end()), d.columns.end());
    d.A.resize(2 * m, 3);
    d.r.resize(2 * m);
    d.B = Eigen::MatrixXd::Zero(2 * m, static_cast<Eigen::Index>(d.columns.size()));
    for (Eigen::Index i = 0; i < m; ++i) {
      const LabelVcView& v = inst[static_cast<std::size_t>(i)];
      d.A.block<2, 3>(2 * i, 0) = v.d_pixel_d_point;
      d.r.segment<2>(2 * i) = v.residual_px;
      for (Eigen::Index j = 0; j < v.d_pixel_d_common.cols(); ++j) {
        const auto local =
            std::lower_bound(d.columns.begin(), d.columns.end(), v.common_offset + j) - d.columns.begin();
        d.B.block<2, 1>(2 * i, local) = v.d_pixel_d_common.col(j);
      }
    }
    out.push_back(std::move(d));
  }
  return out;
}

// The per-instant projector P₀ = W − W·J·(JᵀWJ)⁻¹·JᵀW at `theta`, and the log-determinants of its
// covariance and normal matrix; false when either is singular.
struct VcProjector {
  Eigen::MatrixXd P;
  double log_det_sigma = 0, log_det_n = 0;
  bool ok = false;
};

VcProjector projector(const VcInstantData& d, const Grouping& group, const std::vector<double>& theta) {
  VcProjector out;
  const auto m = static_cast<Eigen::Index>(d.views->size());
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(2 * m, 2 * m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const LabelVcView& v = (*d.views)[static_cast<std::size_t>(i)];
    const Eigen::Matrix2d cov =
        label_variance(v, group, theta) * Eigen::Matrix2d::Identity() + v.fixed_cov_px2;
    const double det = cov.determinant();
    if (!(det > 0)) return out;
    out.log_det_sigma += std::log(det);
    W.block<2, 2>(2 * i, 2 * i) = cov.inverse();
  }
  const Eigen::Matrix3d N = d.A.transpose() * W * d.A;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(N);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return out;
  out.log_det_n = ldlt.vectorD().array().log().sum();
  const Eigen::MatrixXd WA = W * d.A;
  out.P = W - WA * ldlt.solve(WA.transpose());
  out.ok = true;
  return out;
}

// The whole problem at `theta` over the instants kept: each instant's projector, the calibration
// error the residuals show (û) and M⁻¹, and the REML log-likelihood
// −½·Σ(log|Σ| + log|JᵀΣ⁻¹J| + rᵀ·P₀·r) − ½·log|M| + ½·zᵀ·û (z = BᵀP₀r; Harville, JASA 72, 1977).
struct VcCommon {
  std::vector<VcProjector> p0;  // per instant (ok = false: not used)
  Eigen::VectorXd u_hat;
  Eigen::MatrixXd m_inv;
  double loglik = 0;
  bool ok = false;
};

VcCommon common_pass(const std::vector<VcInstantData>& data, const Grouping& group,
                     const std::vector<double>& theta, const std::vector<char>& keep, Eigen::Index q,
                     bool likelihood_only) {
  VcCommon out;
  out.p0.resize(data.size());
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(q, q);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(q);
  for (std::size_t k = 0; k < data.size(); ++k) {
    if (!keep[k]) continue;
    VcProjector pk = projector(data[k], group, theta);
    if (!pk.ok) continue;
    const VcInstantData& d = data[k];
    const Eigen::VectorXd Pr = pk.P * d.r;
    out.loglik -= 0.5 * (pk.log_det_sigma + pk.log_det_n + d.r.dot(Pr));
    if (!d.columns.empty()) {
      const Eigen::MatrixXd PB = pk.P * d.B;
      Y(d.columns, d.columns) += d.B.transpose() * PB;
      z(d.columns) += d.B.transpose() * Pr;
    }
    if (!likelihood_only) out.p0[k] = std::move(pk);
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(Eigen::MatrixXd::Identity(q, q) + Y);
  if (q > 0 && (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0))) return out;
  out.u_hat = q > 0 ? Eigen::VectorXd(ldlt.solve(z)) : Eigen::VectorXd(0);
  if (q > 0) out.loglik += -0.5 * ldlt.vectorD().array().log().sum() + 0.5 * z.dot(out.u_hat);
  if (!likelihood_only)
    out.m_inv = q > 0 ? Eigen::MatrixXd(ldlt.solve(Eigen::MatrixXd::Identity(q, q))) : Eigen::MatrixXd(0, 0);
  out.ok = true;
  return out;
}

// The score and Fisher information per component and each camera's share of the dof, from a common
// pass.
struct VcScores {
  Eigen::VectorXd score;
  Eigen::MatrixXd fisher;
  std::vector<double> redundancy;
  std::size_t instants = 0;
};

VcScores score_pass(const std::vector<VcInstantData>& data, const Grouping& group,
                    const std::vector<double>& theta, const VcCommon& c, std::size_t cameras,
                    Eigen::Index q) {
  const auto K = static_cast<Eigen::Index>(theta.size());
  VcScores out;
  out.score = Eigen::VectorXd::Zero(K);
  out.fisher = Eigen::MatrixXd::Zero(K, K);
  out.redundancy.assign(cameras, 0.0);
  std::vector<Eigen::MatrixXd> G(static_cast<std::size_t>(K), Eigen::MatrixXd::Zero(q, q));
  for (std::size_t n = 0; n < data.size(); ++n) {
    const VcProjector& pk = c.p0[n];
    if (!pk.ok) continue;
    const VcInstantData& d = data[n];
    ++out.instants;
    const auto m = static_cast<Eigen::Index>(d.views->size());
    Eigen::VectorXd e = d.r;
    Eigen::MatrixXd E(2 * m, static_cast<Eigen::Index>(d.columns.size()));
    Eigen::MatrixXd R = Eigen::MatrixXd::Zero(2 * m, 2 * m);
    if (!d.columns.empty()) {
      e -= d.B * c.u_hat(d.columns);
      E = pk.P * d.B;
      R = E * c.m_inv(d.columns, d.columns) * E.transpose();
    }
    const Eigen::VectorXd Pr = pk.P * e;
    for (Eigen::Index i = 0; i < m; ++i) {
      const LabelVcView& vi = (*d.views)[static_cast<std::size_t>(i)];
      const double tr_ii = pk.P.block(2 * i, 2 * i, 2, 2).trace() - R.block(2 * i, 2 * i, 2, 2).trace();
      out.redundancy[vi.camera] += label_variance(vi, group, theta) * tr_ii;
      for (const auto& [k, qi] : label_terms(vi, group)) {
        if (k < 0) continue;
        out.score(k) += 0.5 * qi * (Pr.segment<2>(2 * i).squaredNorm() - tr_ii);
        if (!d.columns.empty()) {
          const Eigen::MatrixXd Ei = E.middleRows(2 * i, 2);
          G[static_cast<std::size_t>(k)](d.columns, d.columns) += qi * Ei.transpose() * Ei;
        }
        for (Eigen::Index j = 0; j < m; ++j) {
          const Eigen::Matrix2d P0 = pk.P.block(2 * i, 2 * j, 2, 2);
          const Eigen::Matrix2d Rij = R.block(2 * i, 2 * j, 2, 2);
          // Same instant: ‖P₀,ij − R_ij‖² less the ‖R_ij‖² counted below with every pair.
          const double same = P0.squaredNorm() - 2 * (P0.transpose() * Rij).trace();
          for (const auto& [l, qj] : label_terms((*d.views)[static_cast<std::size_t>(j)], group))
            if (l >= 0) out.fisher(k, l) += 0.5 * qi * qj * same;
        }
      }
    }
  }
  // Every pair of views, across instants too: Σ‖E_i·M⁻¹·E_jᵀ‖² = tr(M⁻¹·G_k·M⁻¹·G_l).
  if (q > 0) {
    std::vector<Eigen::MatrixXd> MG;
    for (const Eigen::MatrixXd& g : G) MG.push_back(c.m_inv * g);
    for (Eigen::Index a = 0; a < K; ++a)
      for (Eigen::Index b = 0; b < K; ++b)
        out.fisher(a, b) +=
            0.5 *
            (MG[static_cast<std::size_t>(a)].cwiseProduct(MG[static_cast<std::size_t>(b)].transpose())).sum();
  }
  return out;
}

// The instants to use under `theta`: those whose χ² about the calibration error û lies below its
// 99.9 % quantile (config/chi2_quantile.hpp). Cutting there leaves out ~0.1 % of honest instants,
// which lowers a scale by ~1 % at most.
std::vector<char> screen(const std::vector<VcInstantData>& data, const Grouping& group,
                         const std::vector<double>& theta, const Eigen::VectorXd& u_hat) {
  std::vector<char> keep(data.size(), 0);
  for (std::size_t k = 0; k < data.size(); ++k) {
    const VcInstantData& d = data[k];
    const VcProjector pk = projector(d, group, theta);
    if (!pk.ok) continue;
    Eigen::VectorXd e = d.r;
    if (!d.columns.empty()) e -= d.B * u_hat(d.columns);
    keep[k] = e.dot(pk.P * e) <= chi2_quantile_wilson_hilferty(d.dof, kNormalQuantile999) ? 1 : 0;
  }
  return keep;
}

// One solve for a fixed grouping (Grouping above). Fisher scoring on log θ (the scales stay positive) with a
// halving line search on the REML likelihood: from a start far from the estimate a full step can overshoot.
struct VcSolve {
  std::vector<double> theta;  // per component
  Eigen::MatrixXd fisher;     // at the end
  std::vector<double> redundancy;
  std::size_t instants = 0, excluded = 0;
  int iterations = 0;
  bool converged = false;
};

VcSolve solve_vc(const std::vector<VcInstantData>& data, const Grouping& group, int components,
                 std::size_t cameras, Eigen::Index q, const LabelVcOptions& options) {
  VcSolve s;
  s.theta.assign(static_cast<std::size_t>(components), 1.0);
  // The first pass takes every instant: under a stated σ far too small every instant would look
  // gross. After each step, under the new scales, the gross ones are left out of the next.
  std::vector<char> keep(data.size(), 1);
  for (int it = 1; it <= options.max_iterations; ++it) {
    s.iterations = it;
    const VcCommon c = common_pass(data, group, s.theta, keep, q, false);
    if (!c.ok) break;
    const VcScores sc = score_pass(data, group, s.theta, c, cameras, q);
    s.fisher = sc.fisher;
    s.redundancy = sc.redundancy;
    s.instants = sc.instants;
    s.excluded = 0;
    for (char k : keep) s.excluded += k ? 0 : 1;
    if (components == 0) break;  // nothing to estimate: not converged, every camera as given
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(sc.fisher);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) break;
    const Eigen::VectorXd step = ldlt.solve(sc.score);
    std::vector<double> next = s.theta;
    double change = 0;
    bool accepted = false;
    for (double alpha = 1; alpha > 1e-6 && !accepted; alpha /= 2) {
      change = 0;
      for (int k = 0; k < components; ++k) {
        const auto uk = static_cast<std::size_t>(k);
        const double log_step = std::clamp(alpha * step(k) / s.theta[uk], -5.0, 5.0);
        next[uk] = std::max(s.theta[uk] * std::exp(log_step), options.min_scale);
        change = std::max(change, std::abs(std::log(next[uk] / s.theta[uk])));
      }
      const VcCommon trial = common_pass(data, group, next, keep, q, true);
      accepted = trial.ok && trial.loglik >= c.loglik - 1e-12 * std::abs(c.loglik);
    }
    // No step along the Fisher direction raises the likelihood: the score is zero to rounding.
    const bool settled = !accepted || (change < options.tolerance && it > 1);
    if (accepted) s.theta = next;
    // Re-screening stops half-way through the iterations: an instant on the edge of the cut would
    // otherwise flip in and out for ever.
    const std::vector<char> screened =
        it <= options.max_iterations / 2 ? screen(data, group, s.theta, c.u_hat) : keep;
    if (settled && screened == keep) {
      s.converged = true;
      // The information at the final scales, for their covariance.
      const VcCommon f = common_pass(data, group, s.theta, keep, q, false);
      if (f.ok) {
        const VcScores fs = score_pass(data, group, s.theta, f, cameras, q);
        s.fisher = fs.fisher;
        s.redundancy = fs.redundancy;
      }
      break;
    }
    keep = screened;
  }
  return s;
}

// The spread (1σ) of 2w(1 − w) over a camera's views below which its labels' correlation is not
// estimated: 2w(1 − w) runs from 0 on a frame to ½ half-way.
constexpr double kMinWeightSpread = 0.05;

// Cov(θ̂) = Fisher⁻¹; +∞ on the diagonal where the information is singular or the solve did not
// converge.
Eigen::MatrixXd vc_covariance(const VcSolve& s) {
  const auto k = static_cast<Eigen::Index>(s.theta.size());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(k, k);
  out.diagonal().setConstant(std::numeric_limits<double>::infinity());
  if (k == 0 || !s.converged) return out;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(s.fisher);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return out;
  return ldlt.solve(Eigen::MatrixXd::Identity(k, k));
}

}  // namespace

LabelVcResult estimate_label_variance_components(const std::vector<LabelVcInstant>& instants,
                                                 std::size_t cameras, Eigen::Index common_dim,
                                                 const LabelVcOptions& options) {
  const std::vector<VcInstantData> data = prepare(instants);
  // Which cameras have a view in an instant with a degree of freedom: only they can be judged.
  std::vector<bool> judged(cameras, false);
  for (const LabelVcInstant& inst : instants)
    if (2 * static_cast<int>(inst.size()) - 3 >= 1)
      for (const LabelVcView& v : inst) judged.at(v.camera) = true;

  // Start with a scale of its own for every judged camera, its labels' correlation estimated. A
  // correlation the data cannot pin (or above 1) is taken as 1 (the σ whole at any w); then cameras
  // whose scale the data cannot separate share one scale, and a common scale the data cannot
  // determine either is held at the σ given.
  std::vector<LabelScaleKind> kind(cameras, LabelScaleKind::as_given);
  // The two parts are told apart only by how w varies over a camera's instants: a camera whose
  // frames fall at the same place between the instants every time (its rate a multiple of theirs)
  // gives them in one proportion, and its correlation is not estimated.
  std::vector<double> n(cameras, 0), sum(cameras, 0), sum2(cameras, 0);
  for (const VcInstantData& d : data)
    for (const LabelVcView& v : *d.views) {
      const double between = 2 * v.interpolation_weight * (1 - v.interpolation_weight);
      n[v.camera] += 1;
      sum[v.camera] += between;
      sum2[v.camera] += between * between;
    }
  std::vector<char> split(cameras, 0);
  for (std::size_t c = 0; c < cameras; ++c)
    if (judged[c]) {
      kind[c] = LabelScaleKind::own;
      const double mean = sum[c] / n[c];
      split[c] = sum2[c] / n[c] - mean * mean >= kMinWeightSpread * kMinWeightSpread ? 1 : 0;
    }
  VcSolve s;
  Grouping group;
  Eigen::MatrixXd cov;
  // Every change un-splits a camera or moves it on, own → common → as given: this ends.
  for (;;) {
    group.at_frame.assign(cameras, -1);
    group.between.assign(cameras, -1);
    int components = 0;
    int common = -1;
    for (std::size_t c = 0; c < cameras; ++c) {
      if (kind[c] == LabelScaleKind::own) {
        group.at_frame[c] = components++;
        group.between[c] = split[c] ? components++ : group.at_frame[c];
      }
      if (kind[c] == LabelScaleKind::common) {
        if (common < 0) common = components++;
        group.at_frame[c] = group.between[c] = common;
      }
    }
    s = solve_vc(data, group, components, cameras, common_dim, options);
    cov = vc_covariance(s);
    const auto theta = [&](int k) { return s.theta[static_cast<std::size_t>(k)]; };
    // A scale on its lower bound is no estimate: the likelihood wants the labels' variance below
    // what the rest of the views' covariance leaves room for (the calibration's or the clock's σ
    // explains their residuals), and the Fisher σ at a bound means nothing. The labels' σ is then
    // not determined by the views; taken near zero it would give the camera all the weight.
    const auto determined = [&](int k) {
      return theta(k) > options.min_scale * (1 + 1e-9) && std::isfinite(cov(k, k)) &&
             std::sqrt(cov(k, k)) / (2 * theta(k)) <= options.max_relative_sd;
    };
    bool changed = false;
    if (!s.converged)  // a correlation the solve could not separate: all taken as 1, and again
      for (std::size_t c = 0; c < cameras; ++c) {
        changed = changed || split[c];
        split[c] = 0;
      }
    if (changed) continue;
    for (std::size_t c = 0; c < cameras; ++c) {
      if (!split[c]) continue;
      const int a = group.at_frame[c], b = group.between[c];
      // ρ = θ_b/θ_a: pinned to 0.2 (1σ, to first order), at most 1.
      const double ta = theta(a), tb = theta(b);
      const double rho_var = cov(b, b) / (ta * ta) - 2 * tb * cov(a, b) / (ta * ta * ta) +
                             tb * tb * cov(a, a) / (ta * ta * ta * ta);
      const bool pinned =
          std::isfinite(rho_var) && std::sqrt(std::max(0.0, rho_var)) <= options.max_relative_sd;
      if (!determined(a) || !pinned || theta(b) > theta(a)) {
        split[c] = 0;
        changed = true;
      }
    }
    if (changed) continue;
    std::vector<std::size_t> undetermined_own;
    for (std::size_t c = 0; c < cameras; ++c) {
      if (group.at_frame[c] < 0 || determined(group.at_frame[c])) continue;
      if (kind[c] == LabelScaleKind::own) undetermined_own.push_back(c);
      if (kind[c] == LabelScaleKind::common) {
        kind[c] = LabelScaleKind::as_given;
        changed = true;
      }
    }
    if (undetermined_own.size() >= 2 && !changed) {
      for (std::size_t c : undetermined_own) kind[c] = LabelScaleKind::common;
      changed = true;
    } else {
      for (std::size_t c : undetermined_own) kind[c] = LabelScaleKind::as_given;
      changed = changed || !undetermined_own.empty();
    }
    if (!changed) break;
  }

  LabelVcResult out;
  out.sigma_scale.assign(cameras, 1.0);
  out.sigma_scale_sd.assign(cameras, 0.0);
  out.correlation.assign(cameras, 1.0);
  out.correlation_sd.assign(cameras, 0.0);
  out.correlation_estimated.assign(cameras, false);
  out.kind = kind;
  out.redundancy = s.redundancy;
  out.redundancy.resize(cameras, 0.0);
  out.instants = s.instants;
  out.excluded = s.excluded;
  out.iterations = s.iterations;
  out.converged = s.converged;
  for (std::size_t c = 0; c < cameras; ++c) {
    if (group.at_frame[c] < 0 || kind[c] == LabelScaleKind::as_given) continue;
    const int a = group.at_frame[c];
    const double ta = s.theta[static_cast<std::size_t>(a)];
    out.sigma_scale[c] = std::sqrt(ta);
    out.sigma_scale_sd[c] = std::sqrt(cov(a, a)) / (2 * std::sqrt(ta));
    if (split[c]) {
      const int b = group.between[c];
      const double tb = s.theta[static_cast<std::size_t>(b)];
      out.correlation[c] = tb / ta;
      // ρ = θ_b/θ_a to first order.
      out.correlation_sd[c] =
          std::sqrt(std::max(0.0, cov(b, b) / (ta * ta) - 2 * tb * cov(a, b) / (ta * ta * ta) +
                                      tb * tb * cov(a, a) / (ta * ta * ta * ta)));
      out.correlation_estimated[c] = true;
    }
  }
  return out;
}

}  // namespace rangecal
