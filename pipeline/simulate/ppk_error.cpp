#include "pipeline/simulate/ppk_error.hpp"

#include <cmath>

#include "config/deterministic_random.hpp"

namespace rangecal {

std::vector<Eigen::Vector3d> draw_gauss_markov(const Eigen::Vector3d& sd_m, const Eigen::Vector3d& tau_s,
                                               const std::vector<double>& t_s, std::uint64_t seed) {
  RenderRandom rng(seed);
  std::vector<Eigen::Vector3d> g(t_s.size());
  for (std::size_t k = 0; k < t_s.size(); ++k) {
    const Eigen::Vector3d w(rng.normal(), rng.normal(), rng.normal());
    if (k == 0) {
      g[0] = sd_m.cwiseProduct(w);  // the stationary distribution N(0, σ²)
      continue;
    }
    const double dt = t_s[k] - t_s[k - 1];
    for (int a = 0; a < 3; ++a) {
      // φ = exp(−Δt/τ) (ppk_error_model.hpp); 1 − φ² = −expm1(−2Δt/τ), accurate also when Δt ≪ τ.
      const double phi = gauss_markov_transition(dt, tau_s[a]);
      g[k][a] = phi * g[k - 1][a] + sd_m[a] * std::sqrt(-std::expm1(-2.0 * dt / tau_s[a])) * w[a];
    }
  }
  return g;
}

std::vector<Eigen::Vector3d> draw_flight_bias(const Eigen::Vector3d& sd_m, const std::vector<int>& flight,
                                              std::uint64_t seed) {
  std::vector<Eigen::Vector3d> bias(flight.size());
  Eigen::Vector3d current = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < flight.size(); ++k) {
    if (k == 0 || flight[k] != flight[k - 1]) {
      RenderRandom rng(mix_seed(seed, static_cast<std::uint64_t>(flight[k])));
      const Eigen::Vector3d z(rng.normal(), rng.normal(), rng.normal());
      current = sd_m.cwiseProduct(z);
    }
    bias[k] = current;
  }
  return bias;
}

std::vector<Eigen::Vector3d> draw_ppk_correlated_error(const PpkCorrelatedError& model,
                                                       const std::vector<double>& t_s,
                                                       const std::vector<int>& flight, std::uint64_t gm_seed,
                                                       std::uint64_t bias_seed) {
  std::vector<Eigen::Vector3d> e(t_s.size(), Eigen::Vector3d::Zero());
  if (model.has_gauss_markov()) {
    const auto g = draw_gauss_markov(model.gm_sd_m, model.gm_tau_s, t_s, gm_seed);
    for (std::size_t k = 0; k < e.size(); ++k) e[k] += g[k];
  }
  if (model.has_flight_bias()) {
    const auto b = draw_flight_bias(model.flight_bias_sd_m, flight, bias_seed);
    for (std::size_t k = 0; k < e.size(); ++k) e[k] += b[k];
  }
  return e;
}

Eigen::Vector3d reported_sd_m(const Eigen::Vector3d& white_sd_m, const PpkCorrelatedError& model) {
  Eigen::Vector3d sd;
  for (int a = 0; a < 3; ++a) sd[a] = std::hypot(white_sd_m[a], model.gm_sd_m[a]);
  return sd;
}

PpkErrorModel stated_error_model(const Eigen::Vector3d& white_sd_m, const PpkCorrelatedError& model) {
  PpkErrorModel m;
  if (!(model.gm_sd_m.x() > 0 && model.gm_sd_m.z() > 0)) return m;
  const Eigen::Vector3d total = reported_sd_m(white_sd_m, model);
  m.white_scale_h = white_sd_m.x() / total.x(), m.white_scale_v = white_sd_m.z() / total.z();
  m.gm_sd_h_m = model.gm_sd_m.x(), m.gm_sd_v_m = model.gm_sd_m.z();
  m.tau_h_s = model.gm_tau_s.x(), m.tau_v_s = model.gm_tau_s.z();
  return m;
}

}  // namespace rangecal
