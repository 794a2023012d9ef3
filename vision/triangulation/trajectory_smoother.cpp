#include "vision/triangulation/trajectory_smoother.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace rangecal {
namespace {

// The state: position, velocity, acceleration (m, m/s, m/s²) and the labels' error in whitened
// units ε (z = p + L·ε, L·Lᵀ the instant's labels' covariance).
constexpr int kN = 12;
using Vector12d = Eigen::Matrix<double, kN, 1>;
using Matrix12d = Eigen::Matrix<double, kN, kN>;

// At most this many instants enter the likelihood: enough to fix q and τ to a few per cent, and
// the search stays a fraction of the triangulation's time on long records.
constexpr std::size_t kMaxLikelihoodInstants = 2000;

// The labels' error's time constants tried, in median steps between instants (0: white).
constexpr double kLabelTauSteps[] = {0, 1, 2, 4, 8};

// The state moved by dt: F, and the process noise Q for jerk density q and the labels' error's
// correlation φ = exp(−dt/τ) (Bar-Shalom et al. 2001, eq. 6.2.3-8, per axis; the labels' error a
// first-order Gauss–Markov process of unit variance).
void transition(double dt, double q, double phi, Matrix12d* F, Matrix12d* Q) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  F->setIdentity();
  F->block<3, 3>(0, 3) = dt * I;
  F->block<3, 3>(0, 6) = 0.5 * dt * dt * I;
  F->block<3, 3>(3, 6) = dt * I;
  F->block<3, 3>(9, 9) = phi * I;
  Q->setZero();
  const double d2 = dt * dt, d3 = d2 * dt, d4 = d3 * dt, d5 = d4 * dt;
  const double c[3][3] = {{d5 / 20, d4 / 8, d3 / 6}, {d4 / 8, d3 / 3, d2 / 2}, {d3 / 6, d2 / 2, dt}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Q->block<3, 3>(3 * i, 3 * j) = q * c[i][j] * I;
  Q->block<3, 3>(9, 9) = (1 - phi * phi) * I;
}

// L with L·Lᵀ = the labels' covariance of the instant (a floor of 1 µm² keeps an instant stated
// exact from making the filter singular).
Eigen::Matrix3d label_root(const TrajectoryPoint& p) {
  Eigen::Matrix3d R = 0.5 * (p.fix.cov_pick_m2 + p.fix.cov_pick_m2.transpose());
  R += 1e-12 * Eigen::Matrix3d::Identity();
  const Eigen::LLT<Eigen::Matrix3d> llt(R);
  if (llt.info() == Eigen::Success) return llt.matrixL();
  // Not positive definite (rounding in a near-singular covariance): its eigenvalues clamped.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(R);
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(1e-12).cwiseSqrt().asDiagonal();
}

struct SmootherModel {
  double q = 0;      ///< jerk density (m²/s⁵)
  double tau_s = 0;  ///< the labels' error's time constant (s; 0: white)
};

double phi_of(const SmootherModel& m, double dt) {
  return m.tau_s > 0 ? std::exp(-dt / m.tau_s) : 0.0;
}

// The filtered states of a stretch, kept for the smoothing pass (the predictions are recomputed).
struct Filtered {
  std::vector<Vector12d> x;
  std::vector<Matrix12d> P;
};

// The Kalman filter over points [b, e); returns the log-likelihood of the innovations from the
// fourth on (the first three only start the diffuse state: position, velocity, acceleration), and
// keeps the filtered states in `keep` when given.
double kalman_filter(const std::vector<TrajectoryPoint>& pts, std::size_t b, std::size_t e,
                     const SmootherModel& m, Filtered* keep) {
  const std::size_t n = e - b;
  if (keep) keep->x.resize(n), keep->P.resize(n);
  Vector12d x = Vector12d::Zero();
  Matrix12d P = Matrix12d::Zero();
  // Diffuse position, velocity and acceleration (1 km, 1 km/s, 1 km/s²): the fixes decide them.
  P.diagonal().head<9>().setConstant(1e6);
  P.block<3, 3>(9, 9).setIdentity();  // the labels' error: stationary, unit variance
  x.head<3>() = pts[b].fix.point;
  double log_likelihood = 0;
  Matrix12d F, Q;
  for (std::size_t k = 0; k < n; ++k) {
    const TrajectoryPoint& p = pts[b + k];
    if (k > 0) {
      const double dt = seconds_between(pts[b + k - 1].t, p.t);
      transition(dt, m.q, phi_of(m, dt), &F, &Q);
      x = F * x;
      P = F * P * F.transpose() + Q;
    }
    // z = p + L·ε: H = [I 0 0 L].
    const Eigen::Matrix3d L = label_root(p);
    Eigen::Matrix<double, 3, kN> H = Eigen::Matrix<double, 3, kN>::Zero();
    H.block<3, 3>(0, 0).setIdentity();
    H.block<3, 3>(0, 9) = L;
    const Eigen::Vector3d nu = p.fix.point - H * x;
    const Eigen::Matrix<double, kN, 3> PHt = P * H.transpose();
    const Eigen::Matrix3d S = H * PHt + 1e-14 * Eigen::Matrix3d::Identity();
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(S);
    if (k >= 3) log_likelihood -= 0.5 * (ldlt.vectorD().array().log().sum() + nu.dot(ldlt.solve(nu)));
    const Eigen::Matrix<double, kN, 3> K = ldlt.solve(PHt.transpose()).transpose();
    x += K * nu;
    P -= K * S * K.transpose();
    P = 0.5 * (P + P.transpose()).eval();
    if (keep) keep->x[k] = x, keep->P[k] = P;
  }
  return log_likelihood;
}

struct SmoothedStretch {
  std::size_t begin, end;
};

double log_likelihood(const std::vector<TrajectoryPoint>& pts, const std::vector<SmoothedStretch>& stretches,
                      const SmootherModel& m) {
  double L = 0;
  std::size_t used = 0;
  for (const SmoothedStretch& st : stretches) {
    if (used >= kMaxLikelihoodInstants) break;
    const std::size_t end = std::min(st.end, st.begin + (kMaxLikelihoodInstants - used));
    if (end - st.begin >= 3) L += kalman_filter(pts, st.begin, end, m, nullptr);
    used += end - st.begin;
  }
  return L;
}

// The q of largest likelihood for a given τ: every second decade of the range, then a
// golden-section search on log q within two decades of the best. Returns the likelihood.
double best_jerk_psd(const std::vector<TrajectoryPoint>& pts, const std::vector<SmoothedStretch>& stretches,
                     const SmootherOptions& o, SmootherModel* m) {
  const double lo = std::log10(o.min_jerk_psd), hi = std::log10(o.max_jerk_psd);
  const auto L_at = [&](double e) {
    SmootherModel t = *m;
    t.q = std::pow(10.0, e);
    return log_likelihood(pts, stretches, t);
  };
  double best = lo, best_L = -std::numeric_limits<double>::infinity();
  for (double e = lo; e <= hi + 1e-9; e += 2) {
    const double L = L_at(e);
    if (L > best_L) best_L = L, best = e;
  }
  double a = std::max(lo, best - 2), c = std::min(hi, best + 2);
  const double g = (std::sqrt(5.0) - 1) / 2;
  double x1 = c - g * (c - a), x2 = a + g * (c - a);
  double f1 = L_at(x1), f2 = L_at(x2);
  for (int it = 0; it < 16; ++it) {  // 0.618¹⁶ of four decades: q to 0.4 %
    if (f1 > f2) {
      c = x2, x2 = x1, f2 = f1;
      x1 = c - g * (c - a);
      f1 = L_at(x1);
    } else {
      a = x1, x1 = x2, f1 = f2;
      x2 = a + g * (c - a);
      f2 = L_at(x2);
    }
  }
  m->q = std::pow(10.0, 0.5 * (a + c));
  return log_likelihood(pts, stretches, *m);  // the likelihood of the q returned
}

// Rauch–Tung–Striebel over the filter's pass; writes the smoothed state into the points.
void smooth_stretch(std::vector<TrajectoryPoint>* pts, const SmoothedStretch& st, const SmootherModel& m) {
  Filtered f;
  kalman_filter(*pts, st.begin, st.end, m, &f);
  const std::size_t n = st.end - st.begin;
  std::vector<Vector12d>& x = f.x;  // overwritten by the smoothed states, last to first
  std::vector<Matrix12d>& P = f.P;
  Matrix12d F, Q;
  for (std::size_t k = n - 1; k-- > 0;) {
    const double dt = seconds_between((*pts)[st.begin + k].t, (*pts)[st.begin + k + 1].t);
    transition(dt, m.q, phi_of(m, dt), &F, &Q);
    const Vector12d x_pred = F * x[k];
    const Matrix12d P_pred = F * P[k] * F.transpose() + Q;
    const Matrix12d C = Eigen::LDLT<Matrix12d>(P_pred).solve(F * P[k]).transpose();  // P_f·Fᵀ·P_p⁻¹
    x[k] += C * (x[k + 1] - x_pred);
    P[k] += C * (P[k + 1] - P_pred) * C.transpose();
    P[k] = 0.5 * (P[k] + P[k].transpose()).eval();
  }
  for (std::size_t k = 0; k < n; ++k) {
    TrajectoryPoint& p = (*pts)[st.begin + k];
    p.fix.point = x[k].head<3>();
    p.fix.cov_pick_m2 = P[k].block<3, 3>(0, 0);
    p.fix.cov_m2 = p.fix.cov_pick_m2 + p.fix.cov_timing_m2 + p.fix.cov_calibration_m2;
    p.fix.sigma_m = std::sqrt(p.fix.cov_m2.trace());
    p.velocity = x[k].segment<3>(3);
    // The state's: a clock offset is common to the instants and cancels in a velocity; a frame's
    // jitter is left out (in simulation with jitter half the timing variance, velocity z 1.08).
    p.velocity_sd = P[k].block<3, 3>(3, 3).diagonal().cwiseMax(0).cwiseSqrt();
    p.acceleration = x[k].segment<3>(6);
    p.acceleration_sd = P[k].block<3, 3>(6, 6).diagonal().cwiseMax(0).cwiseSqrt();
  }
}

}  // namespace

SmootherReport smooth_trajectory(Trajectory* trajectory, const SmootherOptions& options) {
  SmootherReport r;
  std::vector<TrajectoryPoint>& pts = trajectory->points;
  if (pts.size() < 3) return r;
  const double grid = median_step_s(pts);
  // An instant with a view on an extrapolated lens is left as triangulated and ends a stretch: its
  // lens-model error (in its labels' σ, docs/trajectory.md "Extrapolated views") is common to the
  // instants around it, which the smoother's model of the labels' error is not; and where every
  // view extrapolates, the fix is biased by more than its σ says and the motion model is not to
  // be carried through it.
  const auto left_alone = [&](std::size_t k) { return !pts[k].extrapolated.empty(); };
  std::vector<SmoothedStretch> stretches;
  std::size_t begin = 0;
  for (std::size_t k = 0; k <= pts.size(); ++k) {
    const bool breaks = k == pts.size() || left_alone(k) ||
                        (k > begin && seconds_between(pts[k - 1].t, pts[k].t) > options.gap_steps * grid);
    if (!breaks) continue;
    if (k - begin >= 3) stretches.push_back({begin, k});
    begin = k < pts.size() && left_alone(k) ? k + 1 : k;
  }
  r.stretches = stretches.size();
  if (stretches.empty()) return r;
  // Longest stretches first into the likelihood's budget.
  std::vector<SmoothedStretch> by_length = stretches;
  std::sort(by_length.begin(), by_length.end(), [](const SmoothedStretch& a, const SmoothedStretch& b) {
    return a.end - a.begin > b.end - b.begin;
  });
  SmootherModel best;
  double best_L = -std::numeric_limits<double>::infinity();
  for (const double steps_tau : kLabelTauSteps) {
    SmootherModel m;
    m.tau_s = steps_tau * grid;
    const double L = best_jerk_psd(pts, by_length, options, &m);
    if (L > best_L) best_L = L, best = m;
  }
  r.jerk_psd = best.q;
  r.label_tau_s = best.tau_s;
  for (const SmoothedStretch& st : stretches) {
    smooth_stretch(&pts, st, best);
    r.smoothed += st.end - st.begin;
  }
  return r;
}

}  // namespace rangecal
