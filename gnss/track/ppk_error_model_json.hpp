#pragma once
// The PPK error model (gnss/track/ppk_error_model.hpp) as JSON: one form, written by every output that
// states a model (network.json `statistics.ppk_error_model`, calibration.json `details.ppk_error_model`)
// and read by every input that takes one (the mission config's `gnss.error_model`, those outputs read
// back), so a model a run estimated can be pasted into the next mission's config (docs/gnss.md "PPK
// error model").
//   {"white_scale": s | {"horizontal": s_h, "vertical": s_v},
//    "gauss_markov": null | {"sd_m": σ_g | {…}, "tau_s": τ | {…}}}
// A number stands for both axes. What a run writes beside the values — each value's `sigma`, the
// chained `states`, the `independent_looks`, the `estimate` — is allowed here and read by
// pipeline/io/network_json.hpp; it does not change the model.
#include <nlohmann/json.hpp>

#include "config/json_view.hpp"
#include "gnss/track/ppk_error_model.hpp"

namespace rangecal {

/// Limits of a model that is read (and of what the estimate may reach,
/// optim/network/ppk_error_estimation.cpp): white scale in (0, 10] (a scale above 1 says the .pos sd
/// is optimistic), Gauss–Markov σ_g in [0, 1] m, τ in (0, 1e5] s.
inline constexpr double kMaxWhiteScale = 10;
inline constexpr double kMaxGaussMarkovSdM = 1;
inline constexpr double kMaxGaussMarkovTauS = 1e5;

/// Reads `v` (the form above). Throws `v`'s error kind naming the field: a value outside its limits,
/// an unknown key, a Gauss–Markov part on one axis only (a model correlated on some axes only is not
/// one the network carries), sd_m without tau_s.
PpkErrorModel read_ppk_error_model(const JsonView& v);

/// The model in the form above; `gauss_markov_states` (the network's chained epochs) is written
/// beside a correlated model's values; the Gauss–Markov part is null for a white model.
nlohmann::json ppk_error_model_json(const PpkErrorModel& model, int gauss_markov_states);

}  // namespace rangecal
