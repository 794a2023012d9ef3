// network.json's `ppk_error_model.estimate` (pipeline/io/network_json.hpp): written from a
// PpkErrorEstimate and read back by the report's reader, σ and what was held intact; a held
// parameter's σ is null on disk and NaN read back; a bad field names itself.
#include <gtest/gtest.h>

#include <cmath>

#include "config/error.hpp"
#include "pipeline/io/network_json.hpp"

namespace rangecal {
namespace {

PpkErrorEstimate held_vertical_tau() {
  PpkErrorEstimate e;
  e.model = {0.35, 0.33, 0.008, 0.014, 27, 120};
  e.sd = {0.02, 0.03, 0.001, 0.002, 9, std::nan("")};
  e.likelihood_ratio = 640;
  e.record_s = 143;
  e.gm_sd_held_v = true;
  e.evaluations = 700;
  return e;
}

TEST(PpkErrorEstimateJson, RoundTripsThroughTheReportsReader) {
  const PpkErrorEstimate e = held_vertical_tau();
  nlohmann::json j = ppk_error_model_json(e.model, 240);
  j["estimate"] = ppk_error_estimate_json(e);
  EXPECT_TRUE(j["estimate"]["sd"]["tau_s"]["vertical"].is_null());
  const PpkErrorModelRecord r =
      parse_ppk_error_model_json(nlohmann::json::parse(j.dump()), "network.json", "m");
  EXPECT_TRUE(r.estimated);
  EXPECT_FALSE(r.white_kept);
  EXPECT_FALSE(r.gm_sd_held_h);
  EXPECT_TRUE(r.gm_sd_held_v);
  EXPECT_DOUBLE_EQ(r.record_s, 143);
  EXPECT_DOUBLE_EQ(r.model.tau_v_s, 120);
  EXPECT_DOUBLE_EQ(r.sigma.white_scale_h, 0.02);
  EXPECT_DOUBLE_EQ(r.sigma.gm_sd_v_m, 0.002);
  EXPECT_DOUBLE_EQ(r.sigma.tau_h_s, 9);
  EXPECT_TRUE(std::isnan(r.sigma.tau_v_s));
  EXPECT_EQ(r.states, 240);
}

TEST(PpkErrorEstimateJson, ABadFieldIsNamed) {
  nlohmann::json j = ppk_error_model_json(held_vertical_tau().model, 240);
  j["estimate"] = ppk_error_estimate_json(held_vertical_tau());
  j["estimate"]["gauss_markov_sd_held"]["vertical"] = "yes";
  try {
    parse_ppk_error_model_json(j, "network.json", "ppk_error_model");
    FAIL() << "accepted a string for a flag";
  } catch (const Error& err) {
    EXPECT_NE(std::string(err.what()).find("ppk_error_model.estimate.gauss_markov_sd_held.vertical"),
              std::string::npos)
        << err.what();
  }
}

}  // namespace
}  // namespace rangecal
