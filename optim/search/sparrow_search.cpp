#include "optim/search/sparrow_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "config/deterministic_random.hpp"
#include "config/error.hpp"

namespace rangecal {
namespace {

using Eigen::VectorXd;

constexpr double kInf = std::numeric_limits<double>::infinity();

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

/// The bounds and options sparrow_search accepts (throws rangecal::Error, calibration kind).
void check_search_input(const VectorXd& lb, const VectorXd& ub, const SparrowOptions& opt) {
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

/// The swarm: each sparrow's current position and fitness, its memory (pX, pFit: its best so
/// far), and the global best.
struct Swarm {
  std::vector<VectorXd> x;
  std::vector<double> fit;
  std::vector<VectorXd> pX;
  std::vector<double> pFit;
  VectorXd bestX;
  double fMin = kInf;
};

/// The search's state within an iteration: the objective (counted), the bounds, the random stream.
struct SearchContext {
  const ObjectiveFunction& f;
  const VectorXd& lb;
  const VectorXd& ub;
  const SparrowOptions& opt;
  DeterministicRandom rng;
  SparrowResult* res;

  double eval(const VectorXd& x) {
    ++res->evaluations;
    const double v = f(x);
    return std::isnan(v) ? kInf : v;
  }
  /// x clipped to the box, evaluated into sparrow k.
  void move(Swarm* swarm, int k, const VectorXd& x) {
    swarm->x[k] = clip(x, lb, ub);
    swarm->fit[k] = eval(swarm->x[k]);
  }
};

/// Initial population, uniform in the box; memories pX = x.
Swarm initial_swarm(SearchContext* ctx) {
  const int n = ctx->opt.population;
  const Eigen::Index d = ctx->lb.size();
  Swarm swarm;
  swarm.x.assign(n, VectorXd(d));
  swarm.fit.resize(n);
  for (int i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < d; ++j)
      swarm.x[i][j] = ctx->lb[j] + (ctx->ub[j] - ctx->lb[j]) * ctx->rng.uniform();
    swarm.fit[i] = ctx->eval(swarm.x[i]);
  }
  swarm.pX = swarm.x;
  swarm.pFit = swarm.fit;
  const int ibest =
      static_cast<int>(std::min_element(swarm.pFit.begin(), swarm.pFit.end()) - swarm.pFit.begin());
  swarm.bestX = swarm.pX[ibest];
  swarm.fMin = swarm.pFit[ibest];
  return swarm;
}

/// SA-SSA's starting temperature: the given T0, else −Δ̃/ln(initial acceptance) with Δ̃ the median
/// absolute deviation of the initial memories' finite fitness.
double initial_temperature(const Swarm& swarm, const SparrowOptions& opt) {
  if (opt.sa_T0 > 0) return opt.sa_T0;
  std::vector<double> finite;
  for (double v : swarm.pFit)
    if (std::isfinite(v)) finite.push_back(v);
  double spread = 0;
  if (!finite.empty()) {
    const double med = median(finite);
    std::vector<double> dev;
    for (double v : finite) dev.push_back(std::abs(v - med));
    spread = median(dev);
  }
  if (!(spread > 0)) spread = std::max(std::abs(swarm.fMin), 1.0) * 1e-3;  // flat start: small but > 0
  return -spread / std::log(opt.sa_initial_acceptance);
}

/// 1. Producers (ranks 1..PD).
void move_producers(const std::vector<int>& order, int n_producers, Swarm* swarm, SearchContext* ctx) {
  const int M = ctx->opt.max_iterations;
  const double R2 = ctx->rng.uniform();
  for (int r = 1; r <= n_producers; ++r) {
    const int k = order[r - 1];
    VectorXd y;
    if (R2 < ctx->opt.safety_threshold) {
      const double alpha = ctx->rng.uniform_open_zero();  // α ~ U(0, 1]
      y = swarm->pX[k] * std::exp(-static_cast<double>(r) / (alpha * M));
    } else {
      const double Q = ctx->rng.normal();
      y = swarm->pX[k].array() + Q;  // Q·L: the same shift on every coordinate
    }
    ctx->move(swarm, k, y);
  }
}

/// 2. Scroungers (ranks PD+1..n), towards X_P (the best current position after the producers) or,
/// the hungry half, flying off from X_worst.
void move_scroungers(const std::vector<int>& order, int n_producers, const VectorXd& worse, Swarm* swarm,
                     SearchContext* ctx) {
  const int n = ctx->opt.population;
  const Eigen::Index d = ctx->lb.size();
  const int iP =
      static_cast<int>(std::min_element(swarm->fit.begin(), swarm->fit.end()) - swarm->fit.begin());
  const VectorXd XP = swarm->x[iP];
  for (int r = n_producers + 1; r <= n; ++r) {
    const int k = order[r - 1];
    VectorXd y;
    if (r > n / 2.0) {
      const double Q = ctx->rng.normal();
      y = Q * ((worse - swarm->pX[k]) / (static_cast<double>(r) * r)).array().exp();
    } else {
      // |pX − X_P|·A⁺·L with A ∈ {±1}^d, A⁺ = Aᵀ(AAᵀ)⁻¹ = Aᵀ/d: one scalar on every coordinate.
      double c = 0;
      for (Eigen::Index j = 0; j < d; ++j) c += ctx->rng.sign() * std::abs(swarm->pX[k][j] - XP[j]);
      c /= static_cast<double>(d);
      y = XP.array() + c;
    }
    ctx->move(swarm, k, y);
  }
}

/// 3. Scouts: SD sparrows at random (partial Fisher–Yates).
void move_scouts(int n_scouts, const VectorXd& worse, double fmax, std::vector<int>* perm, Swarm* swarm,
                 SearchContext* ctx) {
  const int n = ctx->opt.population;
  const Eigen::Index d = ctx->lb.size();
  std::iota(perm->begin(), perm->end(), 0);
  for (int s = 0; s < n_scouts; ++s) {
    const int j = s + static_cast<int>(ctx->rng.below(static_cast<std::uint64_t>(n - s)));
    std::swap((*perm)[s], (*perm)[j]);
    const int k = (*perm)[s];
    const VectorXd& pk = swarm->pX[k];
    VectorXd y(d);
    if (swarm->pFit[k] > swarm->fMin) {
      for (Eigen::Index q = 0; q < d; ++q)
        y[q] = swarm->bestX[q] + ctx->rng.normal() * std::abs(pk[q] - swarm->bestX[q]);
    } else {
      const double K = ctx->rng.uniform(-1.0, 1.0);
      y = pk + K * (pk - worse).cwiseAbs() / ((swarm->pFit[k] - fmax) + 1e-50);
    }
    if (!y.allFinite()) y = pk;  // only when every fitness is +∞
    ctx->move(swarm, k, y);
  }
}

/// 4. Greedy memory, global best.
void update_memories(Swarm* swarm) {
  for (std::size_t i = 0; i < swarm->x.size(); ++i) {
    if (swarm->fit[i] < swarm->pFit[i]) {
      swarm->pFit[i] = swarm->fit[i];
      swarm->pX[i] = swarm->x[i];
    }
    if (swarm->pFit[i] < swarm->fMin) {
      swarm->fMin = swarm->pFit[i];
      swarm->bestX = swarm->pX[i];
    }
  }
}

/// 5. SA-SSA: anneal every sparrow's memory at temperature T, Metropolis acceptance, elitist best
/// kept apart. Runs after the greedy update so that no greedy step undoes an accepted worse move.
void anneal_memories(double T, Swarm* swarm, SearchContext* ctx) {
  const VectorXd& lb = ctx->lb;
  const VectorXd& ub = ctx->ub;
  const double sigma = ctx->opt.sa_sigma0 * T / ctx->res->T0;
  for (std::size_t i = 0; i < swarm->x.size(); ++i) {
    VectorXd y(lb.size());
    for (Eigen::Index q = 0; q < lb.size(); ++q)
      y[q] = swarm->pX[i][q] + sigma * (ub[q] - lb[q]) * ctx->rng.normal();
    y = clip(y, lb, ub);
    const double fy = ctx->eval(y);
    ++ctx->res->sa_moves;
    const double delta = fy - swarm->pFit[i];
    const double u = ctx->rng.uniform();  // drawn every time: the stream does not depend on Δ's sign
    const bool accept = delta <= 0 || (std::isfinite(delta) && u < std::exp(-delta / T));
    if (!accept) continue;
    if (delta > 0) ++ctx->res->sa_accepted_worse;
    swarm->pX[i] = y;
    swarm->pFit[i] = fy;
    swarm->x[i] = y;
    swarm->fit[i] = fy;
    if (fy < swarm->fMin) {
      swarm->fMin = fy;
      swarm->bestX = y;
    }
  }
}

}  // namespace

SparrowResult sparrow_search(const ObjectiveFunction& f, const VectorXd& lb, const VectorXd& ub,
                             const SparrowOptions& opt) {
  check_search_input(lb, ub, opt);
  const int n = opt.population;
  const int n_producers = std::clamp(static_cast<int>(std::lround(opt.producer_fraction * n)), 1, n);
  const int n_scouts = std::clamp(static_cast<int>(std::lround(opt.scout_fraction * n)), 0, n);
  SparrowResult res;
  SearchContext ctx{f, lb, ub, opt, DeterministicRandom(opt.seed), &res};
  Swarm swarm = initial_swarm(&ctx);
  double T = 0;
  if (opt.anneal) res.T0 = T = initial_temperature(swarm, opt);

  std::vector<int> order(n);
  std::vector<int> perm(n);
  for (int t = 0; t < opt.max_iterations; ++t) {
    // Rank by memory (stable: ties keep index order, like MATLAB's sort).
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return swarm.pFit[a] < swarm.pFit[b]; });
    // X_worst: current position of the sparrow with the worst memory.
    double fmax = swarm.pFit[0];
    int B = 0;
    for (int i = 1; i < n; ++i)
      if (swarm.pFit[i] > fmax) {  // first maximum, like MATLAB's max
        fmax = swarm.pFit[i];
        B = i;
      }
    const VectorXd worse = swarm.x[B];
    move_producers(order, n_producers, &swarm, &ctx);
    move_scroungers(order, n_producers, worse, &swarm, &ctx);
    move_scouts(n_scouts, worse, fmax, &perm, &swarm, &ctx);
    update_memories(&swarm);
    if (opt.anneal) {
      anneal_memories(T, &swarm, &ctx);
      T *= opt.sa_lambda;
    }
    if (opt.record_history) res.history.push_back(swarm.fMin);
  }
  res.x = swarm.bestX;
  res.f = swarm.fMin;
  res.iterations = opt.max_iterations;
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
