#include "pipeline/io/stated_ppk_error_model.hpp"

#include "pipeline/io/network_json.hpp"

namespace rangecal {

std::optional<StatedPpkErrorModel> stated_ppk_error_model(const CalibrationResult& r,
                                                          const std::string& path) {
  const nlohmann::json& d = r.details;
  if (!d.is_object()) return std::nullopt;
  // The bundle's record first: a network camera's details carry the network's, never their own.
  if (d.contains("ppk_error_model")) {
    const std::string field = "details.ppk_error_model";
    return StatedPpkErrorModel{parse_ppk_error_model_json(d["ppk_error_model"], path, field).model, field};
  }
  if (d.contains("network") && d["network"].is_object() && d["network"].contains("ppk_error_model")) {
    const std::string field = "details.network.ppk_error_model";
    return StatedPpkErrorModel{parse_ppk_error_model_json(d["network"]["ppk_error_model"], path, field).model,
                               field};
  }
  return std::nullopt;
}

bool same_ppk_error_model(const PpkErrorModel& a, const PpkErrorModel& b) {
  return a.white_scale_h == b.white_scale_h && a.white_scale_v == b.white_scale_v &&
         a.gm_sd_h_m == b.gm_sd_h_m && a.gm_sd_v_m == b.gm_sd_v_m && a.tau_h_s == b.tau_h_s &&
         a.tau_v_s == b.tau_v_s;
}

}  // namespace rangecal
