#pragma once
// Sparrow search (SSA, Xue & Shen 2020) and rangecal's simulated-annealing hybrid (SA-SSA), as
// `seeds/SSA.md` specifies them: the original algorithm as its author's own code runs it (seed 002
// §3.2 prints the equations garbled), a generic box-bounded minimiser, deterministic by seed.
//
// SSA is biased toward the origin of its search space (producers shrink coordinates toward 0) and
// toward the diagonal (scroungers and producers add one scalar to every coordinate). On a real
// problem use normalised_sparrow_search(), which searches z ∈ [−1, 1]^d around an initial
// estimate θ0 (θ = θ0 + S·z), so the bias becomes a pull toward θ0, and reports ‖z‖.
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

namespace rangecal {

/// Objective to minimise. May return +∞ (or NaN, treated as +∞) for infeasible points.
using ObjectiveFunction = std::function<double(const Eigen::VectorXd&)>;

struct SparrowOptions {
  int population = 30;             ///< n, number of sparrows
  int max_iterations = 200;        ///< M
  double producer_fraction = 0.2;  ///< PD: producers = round(PD·n) best-ranked sparrows
  double scout_fraction = 0.2;     ///< SD: scouts = round(SD·n) sparrows drawn at random
  double safety_threshold = 0.8;   ///< ST: producers explore widely when R2 ≥ ST
  std::uint64_t seed = 1;          ///< seeds std::mt19937_64 (see deterministic_random.hpp)
  bool record_history = false;     ///< keep the best fitness after every iteration

  // Simulated annealing (SA-SSA, SSA.md); off = plain SSA.
  bool anneal = false;
  double sa_sigma0 = 0.1;  ///< σ0: initial SA step, fraction of (ub − lb) per coordinate
  /// T0; ≤ 0 → automatic: T0 = −Δ̃ / ln(sa_initial_acceptance), Δ̃ = median |f_i − median f| of
  /// the initial population (its robust fitness spread), so a typical worse move is accepted with
  /// probability sa_initial_acceptance (~80 %) at the start.
  double sa_T0 = 0;
  double sa_initial_acceptance = 0.8;
  double sa_lambda = 0.98;  ///< λ: T_{t+1} = λ·T_t, σ_t = σ0·T_t/T0
};

struct SparrowResult {
  Eigen::VectorXd x;            ///< best position found (all-time, elitist)
  double f = 0;                 ///< its fitness
  long evaluations = 0;         ///< objective calls: n + M·(n + SD) for SSA, + M·n for SA-SSA
  int iterations = 0;           ///< M
  std::vector<double> history;  ///< best fitness after each iteration (when asked)
  double T0 = 0;                ///< initial temperature used (SA-SSA)
  long sa_moves = 0;            ///< SA proposals made
  long sa_accepted_worse = 0;   ///< worse SA proposals accepted by Metropolis
};

/// Minimises f over the box [lb, ub] (lb < ub componentwise) by SSA, or SA-SSA when
/// opt.anneal. Throws rangecal::Error (calibration) on inconsistent bounds or options.
SparrowResult sparrow_search(const ObjectiveFunction& f, const Eigen::VectorXd& lb, const Eigen::VectorXd& ub,
                             const SparrowOptions& opt);

struct NormalisedSearchResult {
  Eigen::VectorXd theta;  ///< best parameters θ = θ0 + S·z
  Eigen::VectorXd z;      ///< normalised position of the result, z ∈ [−1, 1]^d
  double z_norm = 0;      ///< ‖z‖₂: how far the search moved from θ0, in half-ranges
  double z_max = 0;       ///< ‖z‖∞
  double f = 0;
  SparrowResult search;  ///< the underlying search (its x is z)
};

/// SSA.md "Using it on calibration": searches θ = θ0 + S·z over z ∈ [−1, 1]^d, S = half_range
/// (> 0 per coordinate, wide enough never to clip the truth).
NormalisedSearchResult normalised_sparrow_search(const ObjectiveFunction& f_theta,
                                                 const Eigen::VectorXd& theta0,
                                                 const Eigen::VectorXd& half_range,
                                                 const SparrowOptions& opt);

}  // namespace rangecal
