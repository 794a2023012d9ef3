#include "gnss/track/ppk_error_model_json.hpp"

#include <string>
#include <utility>

#include "config/number_format.hpp"

namespace rangecal {
namespace {

/// A horizontal / vertical pair: one number for both, or {"horizontal": h, "vertical": v} (a written
/// model's pair may carry its `sigma` too); each in [lo, hi] (excluding lo when `open_low`).
std::pair<double, double> model_axis_pair(const JsonView& v, double lo, double hi, bool open_low,
                                          const std::string& unit) {
  const std::string range = std::string(open_low ? "(" : "[") + format_number("%g", lo) + ", " +
                            format_number("%g", hi) + "] " + unit;
  const std::string form = "a number in " + range + " or {\"horizontal\": h, \"vertical\": v}";
  const auto one = [&](const JsonView& x) {
    const double d = x.number("a number in " + range);
    // An estimate on its upper bound is exp(log bound), which may round one step above it.
    if (!(open_low ? d > lo : d >= lo) || !(d <= hi * (1 + 1e-12))) x.fail_expected("a number in " + range);
    return d;
  };
  if (!v.json().is_object()) {
    if (!v.json().is_number()) v.fail_expected(form);
    const double d = one(v);
    return {d, d};
  }
  v.check_keys({"horizontal", "vertical", "sigma"});
  return {one(v.at("horizontal", "a number in " + range)), one(v.at("vertical", "a number in " + range))};
}

}  // namespace

PpkErrorModel read_ppk_error_model(const JsonView& v) {
  v.require_object("an object {\"white_scale\", \"gauss_markov\": {\"sd_m\", \"tau_s\"}}");
  v.check_keys({"white_scale", "gauss_markov", "estimate"});
  PpkErrorModel m;
  if (auto w = v.find("white_scale"))
    std::tie(m.white_scale_h, m.white_scale_v) =
        model_axis_pair(*w, 0, kMaxWhiteScale, true, "(fraction of the .pos sd)");
  const auto g = v.find("gauss_markov");
  if (!g || g->json().is_null()) return m;
  g->require_object("an object {\"sd_m\", \"tau_s\"} or null");
  g->check_keys({"sd_m", "tau_s", "states", "independent_looks"});
  const JsonView sd = g->at("sd_m", "the Gauss–Markov 1σ in metres");
  std::tie(m.gm_sd_h_m, m.gm_sd_v_m) = model_axis_pair(sd, 0, kMaxGaussMarkovSdM, false, "m");
  std::tie(m.tau_h_s, m.tau_v_s) =
      model_axis_pair(g->at("tau_s", "the correlation time in seconds"), 0, kMaxGaussMarkovTauS, true, "s");
  if ((m.gm_sd_h_m > 0) != (m.gm_sd_v_m > 0))
    sd.fail(
        "a Gauss–Markov part on one axis only; expected sd_m > 0 on both horizontal and vertical, or 0 "
        "on both (a white model)");
  return m;
}

nlohmann::json ppk_error_model_json(const PpkErrorModel& m, int states) {
  const auto hv = [](double h, double v) { return nlohmann::json{{"horizontal", h}, {"vertical", v}}; };
  nlohmann::json j;
  j["white_scale"] = hv(m.white_scale_h, m.white_scale_v);
  j["gauss_markov"] = m.correlated() ? nlohmann::json{{"sd_m", hv(m.gm_sd_h_m, m.gm_sd_v_m)},
                                                      {"tau_s", hv(m.tau_h_s, m.tau_v_s)},
                                                      {"states", states}}
                                     : nlohmann::json();
  return j;
}

}  // namespace rangecal
