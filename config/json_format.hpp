#pragma once
// Deterministic, readable JSON output for the project's JSON files (calibration.json,
// summary.json, run.json, …).
#include <nlohmann/json.hpp>
#include <string>

namespace rangecal {

/// JSON text with 2-space indentation where arrays of scalars stay on one line and matrices
/// (arrays of arrays of scalars) print one row per line; trailing newline. Keys keep the
/// ordered_json insertion order. Numbers are printed as nlohmann prints them: the shortest text
/// that reads back to the same double (so write → read is exact); NaN and ±inf become null.
std::string dump_json_compact_arrays(const nlohmann::ordered_json& j);

}  // namespace rangecal
