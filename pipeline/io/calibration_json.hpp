#pragma once
// `<cam>/calibration.json` (docs/outputs.md): the one result format every calibration method writes and
// every consumer (project, intersect, report) reads. Field names, units and conventions are in
// docs/outputs.md. Writing is deterministic (same result → byte-identical text) and numbers are
// printed in the shortest form that reads back to the same double, so write → read is exact.
#include <array>
#include <nlohmann/json.hpp>
#include <string>

#include "vision/camera/calibration_result.hpp"

namespace rangecal {

/// The keys of the distortion coefficients in calibration.json's "distortion" object (and in
/// truth.json), in Distortion::as_array() order, each with its unit in the name: k1_per_mm2 …
const std::array<const char*, 7>& distortion_json_keys();

/// The calibration.json document for `r` (keys in a fixed, readable order). NaN values (σ not
/// estimated, statistics without observations) are written as null.
nlohmann::ordered_json calibration_to_json(const CalibrationResult& r);

/// calibration.json text: 2-space indentation, arrays of numbers on one line, trailing newline.
std::string calibration_to_json_text(const CalibrationResult& r);

/// Parses and validates calibration.json text. `file` is used in messages. Throws rangecal::Error
/// (kind input) naming the file and the key: unknown keys, wrong types, missing required keys,
/// impossible values (non-positive sizes/focal length, R not a rotation, centre inconsistent with
/// R and T, covariance of the wrong shape).
CalibrationResult calibration_from_json_text(const std::string& text, const std::string& file);

/// Writes calibration.json atomically (config/atomic_file.hpp).
void write_calibration_json(const std::string& path, const CalibrationResult& r);

/// Reads and validates a calibration.json file (errors as calibration_from_json_text; a missing
/// file is an input error naming it).
CalibrationResult read_calibration_json(const std::string& path);

/// The site origin of `r`'s world frame, for geodetic input and output. Throws rangecal::Error
/// (input, naming `path` and the key world_frame) when the file has none — one written before
/// calibration.json recorded it — so geodetic coordinates are unavailable for it.
const GeodeticOrigin& require_site_origin(const CalibrationResult& r, const std::string& path);

}  // namespace rangecal
