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

}  // namespace

SparrowResult sparrow_search(const ObjectiveFunction& f, const VectorXd& lb, const VectorXd& ub,
                             const SparrowOptions& opt) {
  const Eigen::Index d = lb.size();
  if (d < 1 || ub.size() != d)
    throw_calibration_error("sparrow_search", "bounds must be non-empty and of equal size");
  for (Eigen::Index j = 0; j < d; ++j)
    if (!(std::isfinite(lb[j]) && std::isfinite(ub[j]) && lb[j] < ub[j]))
      throw_calibration_error("sparrow_search",
                              "bound " + std::to_string(j) + " is not a finite interval lb < ub");
  const int n = opt.population;
  const int M = opt.max_iterations;
  if (n < 2 || M < 1)
    throw_calibration_error("sparrow_search", "population must be ≥ 2 and max_iterations ≥ 1");
  const int n_producers = std::clamp(static_cast<int>(std::lround(opt.producer_fraction * n)), 1, n);
  const int n_scouts = std::clamp(static_cast<int>(std::lround(opt.scout_fraction * n)), 0, n);
  if (opt.anneal && !(opt.sa_lambda > 0 && opt.sa_lambda <= 1 && opt.sa_sigma0 > 0 &&
                      opt.sa_initial_acceptance > 0 && opt.sa_initial_acceptance < 1))
    throw_calibration_error("sparrow_search",
                            "SA options need 0 < λ ≤ 1, σ0 > 0, 0 < initial acceptance < 1");

  DeterministicRandom rng(opt.seed);
  SparrowResult res;
  auto eval = [&](const VectorXd& x) {
    ++res.evaluations;
    const double v = f(x);
    return std::isnan(v) ? kInf : v;
  };

  // Initial population, uniform in the box; memories pX = x.
  std::vector<VectorXd> x(n, VectorXd(d));
  std::vector<double> fit(n);
  for (int i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < d; ++j) x[i][j] = lb[j] + (ub[j] - lb[j]) * rng.uniform();
    fit[i] = eval(x[i]);
  }
  std::vector<VectorXd> pX = x;
  std::vector<double> pFit = fit;
  int ibest = static_cast<int>(std::min_element(pFit.begin(), pFit.end()) - pFit.begin());
  VectorXd bestX = pX[ibest];
  double fMin = pFit[ibest];

  double T = 0;
  if (opt.anneal) {
    if (opt.sa_T0 > 0) {
      T = opt.sa_T0;
    } else {
      std::vector<double> finite;
      for (double v : pFit)
        if (std::isfinite(v)) finite.push_back(v);
      double spread = 0;
      if (!finite.empty()) {
        const double med = median(finite);
        std::vector<double> dev;
        for (double v : finite) dev.push_back(std::abs(v - med));
        spread = median(dev);
      }
      if (!(spread > 0)) spread = std::max(std::abs(fMin), 1.0) * 1e-3;  // flat start: small but > 0
      T = -spread / std::log(opt.sa_initial_acceptance);
    }
    res.T0 = T;
  }

  std::vector<int> order(n);
  std::vector<int> perm(n);
  for (int t = 0; t < M; ++t) {
    // Rank by memory (stable: ties keep index order, like MATLAB's sort).
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return pFit[a] < pFit[b]; });
    // X_worst: current position of the sparrow with the worst memory.
    double fmax = pFit[0];
    int B = 0;
    for (int i = 1; i < n; ++i)
      if (pFit[i] > fmax) fmax = pFit[i], B = i;  // first maximum, like MATLAB's max
    const VectorXd worse = x[B];

    // 1. Producers (ranks 1..PD).
    const double R2 = rng.uniform();
    for (int r = 1; r <= n_producers; ++r) {
      const int k = order[r - 1];
      if (R2 < opt.safety_threshold) {
        const double alpha = rng.uniform_open_zero();  // α ~ U(0, 1]
        x[k] = pX[k] * std::exp(-static_cast<double>(r) / (alpha * M));
      } else {
        const double Q = rng.normal();
        x[k] = pX[k].array() + Q;  // Q·L: the same shift on every coordinate
      }
      x[k] = clip(x[k], lb, ub);
      fit[k] = eval(x[k]);
    }
    // X_P: best current position after the producer step.
    const int iP = static_cast<int>(std::min_element(fit.begin(), fit.end()) - fit.begin());
    const VectorXd XP = x[iP];

    // 2. Scroungers (ranks PD+1..n).
    for (int r = n_producers + 1; r <= n; ++r) {
      const int k = order[r - 1];
      if (r > n / 2.0) {
        const double Q = rng.normal();
        x[k] = Q * ((worse - pX[k]) / (static_cast<double>(r) * r)).array().exp();
      } else {
        // |pX − X_P|·A⁺·L with A ∈ {±1}^d, A⁺ = Aᵀ(AAᵀ)⁻¹ = Aᵀ/d: one scalar on every coordinate.
        double c = 0;
        for (Eigen::Index j = 0; j < d; ++j) c += rng.sign() * std::abs(pX[k][j] - XP[j]);
        c /= static_cast<double>(d);
        x[k] = XP.array() + c;
      }
      x[k] = clip(x[k], lb, ub);
      fit[k] = eval(x[k]);
    }

    // 3. Scouts: SD sparrows at random (partial Fisher–Yates).
    std::iota(perm.begin(), perm.end(), 0);
    for (int s = 0; s < n_scouts; ++s) {
      const int j = s + static_cast<int>(rng.below(static_cast<std::uint64_t>(n - s)));
      std::swap(perm[s], perm[j]);
      const int k = perm[s];
      VectorXd y(d);
      if (pFit[k] > fMin) {
        for (Eigen::Index q = 0; q < d; ++q) y[q] = bestX[q] + rng.normal() * std::abs(pX[k][q] - bestX[q]);
      } else {
        const double K = rng.uniform(-1.0, 1.0);
        y = pX[k] + K * (pX[k] - worse).cwiseAbs() / ((pFit[k] - fmax) + 1e-50);
      }
      if (!y.allFinite()) y = pX[k];  // only when every fitness is +∞
      x[k] = clip(y, lb, ub);
      fit[k] = eval(x[k]);
    }

    // 4. Greedy memory, global best.
    for (int i = 0; i < n; ++i) {
      if (fit[i] < pFit[i]) {
        pFit[i] = fit[i];
        pX[i] = x[i];
      }
      if (pFit[i] < fMin) {
        fMin = pFit[i];
        bestX = pX[i];
      }
    }

    // 5. SA-SSA: anneal every sparrow's memory, Metropolis acceptance, elitist best kept apart.
    //    Runs after the greedy update so that no greedy step undoes an accepted worse move.
    if (opt.anneal) {
      const double sigma = opt.sa_sigma0 * T / res.T0;
      for (int i = 0; i < n; ++i) {
        VectorXd y(d);
        for (Eigen::Index q = 0; q < d; ++q) y[q] = pX[i][q] + sigma * (ub[q] - lb[q]) * rng.normal();
        y = clip(y, lb, ub);
        const double fy = eval(y);
        ++res.sa_moves;
        const double delta = fy - pFit[i];
        const double u = rng.uniform();  // drawn every time: the stream does not depend on Δ's sign
        const bool accept = delta <= 0 || (std::isfinite(delta) && u < std::exp(-delta / T));
        if (!accept) continue;
        if (delta > 0) ++res.sa_accepted_worse;
        pX[i] = y;
        pFit[i] = fy;
        x[i] = y;
        fit[i] = fy;
        if (fy < fMin) {
          fMin = fy;
          bestX = y;
        }
      }
      T *= opt.sa_lambda;
    }
    if (opt.record_history) res.history.push_back(fMin);
  }
  res.x = bestX;
  res.f = fMin;
  res.iterations = M;
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
