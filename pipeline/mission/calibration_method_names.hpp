#pragma once
// The names of the calibrate stage's methods (docs/optimisation.md), in the order of the method
// table of pipeline/steps/calibration_methods.cpp, which runs them. Header-only, beside the mission
// config that checks calibrate.method and compare against it (pipeline/mission, below the steps and
// the stage table of pipeline/io, which name the methods too) without linking the methods.
#include <array>
#include <string>
#include <vector>

namespace rangecal {

/// tsai, tsai_sassa, dlt_lmqn, bundle, network, planar: the index of each is its row in the
/// method table.
inline constexpr std::array<const char*, 6> kCalibrationMethodNames = {"tsai",   "tsai_sassa", "dlt_lmqn",
                                                                       "bundle", "network",    "planar"};

/// kCalibrationMethodNames as strings (what calibrate.method and compare may name).
inline const std::vector<std::string>& calibration_method_names() {
  static const std::vector<std::string> names(kCalibrationMethodNames.begin(), kCalibrationMethodNames.end());
  return names;
}

}  // namespace rangecal
