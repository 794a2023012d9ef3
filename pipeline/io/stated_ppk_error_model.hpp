#pragma once
// The PPK error model a calibration.json states its σ under (docs/accuracy_analysis.md "World noise
// under the PPK error model"), for `rangecal montecarlo` to draw its world noise under: the per-camera
// bundle's details.ppk_error_model (written only for a model other than its own white weighting,
// pipeline/io/method_details_json.hpp) or the network's details.network.ppk_error_model (the model it
// weighed the fixes by, configured or estimated; pipeline/io/network_json.hpp).
#include <optional>
#include <string>

#include "gnss/track/ppk_error_model.hpp"
#include "vision/camera/calibration_result.hpp"

namespace rangecal {

struct StatedPpkErrorModel {
  PpkErrorModel model;
  std::string field;  ///< where it was read: "details.ppk_error_model" or "details.network.ppk_error_model"
};

/// The model `r` (read from `path`, for messages) records; nullopt when it records none (a bundle
/// under its own weighting, a method that does not read the model). Throws rangecal::Error (input)
/// naming the field for a malformed record.
std::optional<StatedPpkErrorModel> stated_ppk_error_model(const CalibrationResult& r,
                                                          const std::string& path);

/// The same model, field by field (a JSON round trip keeps every double).
bool same_ppk_error_model(const PpkErrorModel& a, const PpkErrorModel& b);

}  // namespace rangecal
