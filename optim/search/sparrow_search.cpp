#include "optim/search/sparrow_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "config/deterministic_random.hpp"
#include "config/error.hpp"

namespace rangecal {
namespace {

using Eigen::VectorXd;

constexpr double kNoFitness = std::numeric_limits<double>::infinity();

VectorXd clip(VectorXd x, const VectorXd& lb, const VectorXd& ub) {
  // SSA.md: out-of-bounds coordinates are clipped (the author's Bounds()).
  for (Eigen::Index j = 0; j < x.size(); ++j) x[j] = std::min(std::max(x[j], lb[j]), ub[j]);
  return x;
}

double median(std::vector<double> v) {
  const std::size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + m, v.end());
  double med = v[m];
  if (v.size() % 2 == 0) med = 0.5 * (med + *std::max_element(v.begin(), v.begin() + m));
  return med;
}

void check_search_inputs(const VectorXd& lb, const VectorXd& ub, const SparrowOptions& opt) {
  const Eigen::Index d = lb.size();
  if (d < 1 || ub.size() != d)
    throw_calibration_error("sparrow_search", "bounds must be non-empty and of equal size");
  for (Eigen::Index j = 0; j < d; ++j)
    if (!(std::isfinite(lb[j]) && std::isfinite(ub[j]) && lb[j] < ub[j]))
      throw_calibration_error("sparrow_search",
                              "bound " + std::to_string(j) + " is not a finite interval lb < ub");
  if (opt.population < 2 || opt.max_iterations < 1)
    throw_calibration_error("sparrow_search", "population must be ≥ 2 and max_iterations ≥ 1");
  if (opt.anneal && !(opt.sa_lambda > 0 && opt.sa_lambda <= 1 && opt.sa_sigma0 > 0 &&
                      opt.sa_initial_acceptance > 0 && opt.sa_initial_acceptance < 1))
    throw_calibration_error("sparrow_search",
                            "SA options need 0 < λ ≤ 1, σ0 > 0, 0 < initial acceptance < 1");
}

/// What every phase reads: the objective (its calls counted, NaN taken as +∞), the box, the
/// options and the one random stream (the phases draw from it in the order of SSA.md).
struct Search {
  const ObjectiveFunction& f;
  const VectorXd& lb;
  const VectorXd& ub;
  const SparrowOptions& opt;
  DeterministicRandom& rng;
  SparrowResult* res;
  Eigen::Index d;
  int n, M;

  double eval(const VectorXd& x) const {
    ++res->evaluations;
    const double v = f(x);
    return std::isnan(v) ? kNoFitness : v;
  }
};

/// The sparrows: current positions and fitness, memories pX (each one's best) and the all-time
/// best (elitist).
struct Flock {
  std::vector<VectorXd> x, pX;
  std::vector<double> fit, pFit;
  VectorXd bestX;
  double fMin = kNoFitness;
};

/// An iteration's ranking by memory, and X_worst: the current position of the sparrow with the
/// worst memory (fmax).
struct Ranking {
  std::vector<int> order;
  double fmax = 0;
  VectorXd worse;
};

/// Initial population, uniform in the box; memories pX = x.
Flock initial_flock(const Search& s) {
  Flock fl;
  fl.x.assign(s.n, VectorXd(s.d));
  fl.fit.resize(s.n);
  for (int i = 0; i < s.n; ++i) {
    for (Eigen::Index j = 0; j < s.d; ++j) fl.x[i][j] = s.lb[j] + (s.ub[j] - s.lb[j]) * s.rng.uniform();
    fl.fit[i] = s.eval(fl.x[i]);
  }
  fl.pX = fl.x;
  fl.pFit = fl.fit;
  const int ibest = static_cast<int>(std::min_element(fl.pFit.begin(), fl.pFit.end()) - fl.pFit.begin());
  fl.bestX = fl.pX[ibest];
  fl.fMin = fl.pFit[ibest];
  return fl;
}

/// SA-SSA's T0: given, or from the initial spread of the finite fitness values (SSA.md).
double initial_temperature(const Flock& fl, const SparrowOptions& opt) {
  if (opt.sa_T0 > 0) return opt.sa_T0;
  std::vector<double> finite;
  for (double v : fl.pFit)
    if (std::isfinite(v)) finite.push_back(v);
  double spread = 0;
  if (!finite.empty()) {
    const double med = median(finite);
    std::vector<double> dev;
    for (double v : finite) dev.push_back(std::abs(v - med));
    spread = median(dev);
  }
  if (!(spread > 0)) spread = std::max(std::abs(fl.fMin), 1.0) * 1e-3;  // flat start: small but > 0
  return -spread / std::log(opt.sa_initial_acceptance);
}

Ranking rank_by_memory(const Flock& fl, int n) {
  Ranking rk;
  // Rank by memory (stable: ties keep index order, like MATLAB's sort).
  rk.order.resize(n);
  std::iota(rk.order.begin(), rk.order.end(), 0);
  std::stable_sort(rk.order.begin(), rk.order.end(), [&](int a, int b) { return fl.pFit[a] < fl.pFit[b]; });
  rk.fmax = fl.pFit[0];
  int B = 0;
  for (int i = 1; i < n; ++i)
    if (fl.pFit[i] > rk.fmax) rk.fmax = fl.pFit[i], B = i;  // first maximum, like MATLAB's max
  rk.worse = fl.x[B];
  return rk;
}

/// 1. Producers (ranks 1..PD).
void move_producers(const Search& s, const Ranking& rk, int n_producers, Flock* fl) {
  const double R2 = s.rng.uniform();
  for (int r = 1; r <= n_producers; ++r) {
    const int k = rk.order[r - 1];
    if (R2 < s.opt.safety_threshold) {
      const double alpha = s.rng.uniform_open_zero();  // α ~ U(0, 1]
      fl->x[k] = fl->pX[k] * std::exp(-static_cast<double>(r) / (alpha * s.M));
    } else {
      const double Q = s.rng.normal();
      fl->x[k] = fl->pX[k].array() + Q;  // Q·L: the same shift on every coordinate
    }
    fl->x[k] = clip(fl->x[k], s.lb, s.ub);
    fl->fit[k] = s.eval(fl->x[k]);
  }
}

/// 2. Scroungers (ranks PD+1..n), following X_P: the best current position after the producers.
void move_scroungers(const Search& s, const Ranking& rk, int n_producers, Flock* fl) {
  const int iP = static_cast<int>(std::min_element(fl->fit.begin(), fl->fit.end()) - fl->fit.begin());
  const VectorXd XP = fl->x[iP];
  for (int r = n_producers + 1; r <= s.n; ++r) {
    const int k = rk.order[r - 1];
    if (r > s.n / 2.0) {
      const double Q = s.rng.normal();
      fl->x[k] = Q * ((rk.worse - fl->pX[k]) / (static_cast<double>(r) * r)).array().exp();
    } else {
      // |pX − X_P|·A⁺·L with A ∈ {±1}^d, A⁺ = Aᵀ(AAᵀ)⁻¹ = Aᵀ/d: one scalar on every coordinate.
      double c = 0;
      for (Eigen::Index j = 0; j < s.d; ++j) c += s.rng.sign() * std::abs(fl->pX[k][j] - XP[j]);
      c /= static_cast<double>(s.d);
      fl->x[k] = XP.array() + c;
    }
    fl->x[k] = clip(fl->x[k], s.lb, s.ub);
    fl->fit[k] = s.eval(fl->x[k]);
  }
}

/// 3. Scouts: SD sparrows at random (partial Fisher–Yates).
void move_scouts(const Search& s, const Ranking& rk, int n_scouts, Flock* fl) {
  std::vector<int> perm(s.n);
  std::iota(perm.begin(), perm.end(), 0);
  for (int q0 = 0; q0 < n_scouts; ++q0) {
    const int j = q0 + static_cast<int>(s.rng.below(static_cast<std::uint64_t>(s.n - q0)));
    std::swap(perm[q0], perm[j]);
    const int k = perm[q0];
    VectorXd y(s.d);
    if (fl->pFit[k] > fl->fMin) {
      for (Eigen::Index q = 0; q < s.d; ++q)
        y[q] = fl->bestX[q] + s.rng.normal() * std::abs(fl->pX[k][q] - fl->bestX[q]);
    } else {
      const double K = s.rng.uniform(-1.0, 1.0);
      y = fl->pX[k] + K * (fl->pX[k] - rk.worse).cwiseAbs() / ((fl->pFit[k] - rk.fmax) + 1e-50);
    }
    if (!y.allFinite()) y = fl->pX[k];  // only when every fitness is +∞
    fl->x[k] = clip(y, s.lb, s.ub);
    fl->fit[k] = s.eval(fl->x[k]);
  }
}

/// 4. Greedy memory, global best.
void keep_memories(Flock* fl) {
  for (std::size_t i = 0; i < fl->x.size(); ++i) {
    if (fl->fit[i] < fl->pFit[i]) {
      fl->pFit[i] = fl->fit[i];
      fl->pX[i] = fl->x[i];
    }
    if (fl->pFit[i] < fl->fMin) {
      fl->fMin = fl->pFit[i];
      fl->bestX = fl->pX[i];
    }
  }
}

/// 5. SA-SSA: anneal every sparrow's memory at temperature T, Metropolis acceptance, elitist best
///    kept apart. Runs after the greedy update so that no greedy step undoes an accepted worse move.
void anneal_memories(const Search& s, double T, Flock* fl) {
  const double sigma = s.opt.sa_sigma0 * T / s.res->T0;
  for (int i = 0; i < s.n; ++i) {
    VectorXd y(s.d);
    for (Eigen::Index q = 0; q < s.d; ++q) y[q] = fl->pX[i][q] + sigma * (s.ub[q] - s.lb[q]) * s.rng.normal();
    y = clip(y, s.lb, s.ub);
    const double fy = s.eval(y);
    ++s.res->sa_moves;
    const double delta = fy - fl->pFit[i];
    const double u = s.rng.uniform();  // drawn every time: the stream does not depend on Δ's sign
    const bool accept = delta <= 0 || (std::isfinite(delta) && u < std::exp(-delta / T));
    if (!accept) continue;
    if (delta > 0) ++s.res->sa_accepted_worse;
    fl->pX[i] = y;
    fl->pFit[i] = fy;
    fl->x[i] = y;
    fl->fit[i] = fy;
    if (fy < fl->fMin) {
      fl->fMin = fy;
      fl->bestX = y;
    }
  }
}

}  // namespace

SparrowResult sparrow_search(const ObjectiveFunction& f, const VectorXd& lb, const VectorXd& ub,
                             const SparrowOptions& opt) {
  check_search_inputs(lb, ub, opt);
  const int n = opt.population;
  const int n_producers = std::clamp(static_cast<int>(std::lround(opt.producer_fraction * n)), 1, n);
  const int n_scouts = std::clamp(static_cast<int>(std::lround(opt.scout_fraction * n)), 0, n);
  DeterministicRandom rng(opt.seed);
  SparrowResult res;
  const Search s{f, lb, ub, opt, rng, &res, lb.size(), n, opt.max_iterations};

  Flock fl = initial_flock(s);
  double T = 0;
  if (opt.anneal) {
    T = initial_temperature(fl, opt);
    res.T0 = T;
  }
  for (int t = 0; t < s.M; ++t) {
    const Ranking rk = rank_by_memory(fl, n);
    move_producers(s, rk, n_producers, &fl);
    move_scroungers(s, rk, n_producers, &fl);
    move_scouts(s, rk, n_scouts, &fl);
    keep_memories(&fl);
    if (opt.anneal) {
      anneal_memories(s, T, &fl);
      T *= opt.sa_lambda;
    }
    if (opt.record_history) res.history.push_back(fl.fMin);
  }
  res.x = fl.bestX;
  res.f = fl.fMin;
  res.iterations = s.M;
  return res;
}

NormalisedSearchResult normalised_sparrow_search(const ObjectiveFunction& f_theta, const VectorXd& theta0,
                                                 const VectorXd& half_range, const SparrowOptions& opt) {
  const Eigen::Index d = theta0.size();
  if (half_range.size() != d) throw_calibration_error("normalised_sparrow_search", "θ0 and S differ in size");
  for (Eigen::Index j = 0; j < d; ++j)
    if (!(half_range[j] > 0 && std::isfinite(half_range[j]) && std::isfinite(theta0[j])))
      throw_calibration_error(
          "normalised_sparrow_search",
          "θ0 must be finite and every half-range S > 0 (coordinate " + std::to_string(j) + ")");
  auto g = [&](const VectorXd& z) -> double { return f_theta(theta0 + half_range.cwiseProduct(z)); };
  NormalisedSearchResult out;
  out.search = sparrow_search(g, VectorXd::Constant(d, -1.0), VectorXd::Constant(d, 1.0), opt);
  out.z = out.search.x;
  out.theta = theta0 + half_range.cwiseProduct(out.z);
  out.z_norm = out.z.norm();
  out.z_max = out.z.cwiseAbs().maxCoeff();
  out.f = out.search.f;
  return out;
}

}  // namespace rangecal
