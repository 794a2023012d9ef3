#pragma once
// The time-correlated part of a simulated PPK position error (docs/simulator.md "PPK error model"):
// per ENU axis a first-order Gauss–Markov
// (GM) process and a constant bias per flight, added to the white noise the simulator draws per epoch
// (ScenarioGnss::noise_sd_m). Real carrier-phase errors stay correlated for tens of seconds to
// minutes (multipath, troposphere), and an ambiguity fix holds an offset until lock is lost; white
// noise alone makes every epoch an independent look at the truth.
//
// This is the truth a simulated receiver draws from, not the network's model of it
// (gnss/track/ppk_error_model.hpp): per E, N, U axis in metres, with a per-flight bias the model has
// no term for. stated_error_model below maps it onto the model.
#include <Eigen/Core>

#include <cstdint>
#include <vector>
#include "gnss/track/ppk_error_model.hpp"

namespace rangecal {

/// Parameters of the correlated error, per axis E, N, U. All-zero sd (the default) = white noise only.
struct PpkCorrelatedError {
  Eigen::Vector3d gm_sd_m = Eigen::Vector3d::Zero();           ///< GM stationary 1σ (m)
  Eigen::Vector3d gm_tau_s = Eigen::Vector3d::Constant(30.0);  ///< GM correlation time τ (s), > 0
  Eigen::Vector3d flight_bias_sd_m = Eigen::Vector3d::Zero();  ///< 1σ of the per-flight bias (m)

  bool has_gauss_markov() const { return (gm_sd_m.array() > 0).any(); }
  bool has_flight_bias() const { return (flight_bias_sd_m.array() > 0).any(); }
  bool active() const { return has_gauss_markov() || has_flight_bias(); }
};

/// A first-order GM series at the times `t_s` (non-decreasing, any spacing), per axis, by the exact
/// discretisation: g₀ ~ N(0, σ²) (stationary start), φ_k = exp(−Δt_k/τ),
/// g_k = φ_k g_{k−1} + σ√(1 − φ_k²) w_k (Brown & Hwang; Gelb). A gap in the times is one long step, so
/// the process runs through it and decorrelates over it. Draws 3 normals per time from the
/// xoshiro256** stream `seed` (config/deterministic_random.hpp).
std::vector<Eigen::Vector3d> draw_gauss_markov(const Eigen::Vector3d& sd_m, const Eigen::Vector3d& tau_s,
                                               const std::vector<double>& t_s, std::uint64_t seed);

/// One N(0, σ²) bias per axis per flight, held over the flight: element k is the bias of flight
/// `flight[k]` (indices ≥ 0; flight f draws from the stream mix_seed(seed, f), so a flight's bias does
/// not depend on the others).
std::vector<Eigen::Vector3d> draw_flight_bias(const Eigen::Vector3d& sd_m, const std::vector<int>& flight,
                                              std::uint64_t seed);

/// GM + per-flight bias at the epochs (times `t_s`, flights `flight`, same length); the GM from
/// stream `gm_seed`, the biases from `bias_seed`. Zero where the model has no correlated part.
std::vector<Eigen::Vector3d> draw_ppk_correlated_error(const PpkCorrelatedError& model,
                                                       const std::vector<double>& t_s,
                                                       const std::vector<int>& flight, std::uint64_t gm_seed,
                                                       std::uint64_t bias_seed);

/// The 1σ a receiver reports per axis (the .pos sdn/sde/sdu): √(white² + σ_GM²). RTKLIB reports the
/// whole variance of an epoch, not its correlation, and knows nothing of a bias.
Eigen::Vector3d reported_sd_m(const Eigen::Vector3d& white_sd_m, const PpkCorrelatedError& model);

/// The network's error model of these errors (gnss/track/ppk_error_model.hpp; docs/gnss.md "PPK
/// error model"): the white part as a fraction of the reported sd, the GM sd and τ (E for
/// horizontal, U for vertical). White (the default model) without a GM part on both axes; a
/// per-flight bias is not in it.
PpkErrorModel stated_error_model(const Eigen::Vector3d& white_sd_m, const PpkCorrelatedError& model);

}  // namespace rangecal
