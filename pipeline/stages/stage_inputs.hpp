#pragma once
// What the stages share when reading their inputs: the check that an earlier stage's output is
// there, with a message that says which stage to run.
#include <string>

namespace rangecal {

/// Throws rangecal::Error (input) naming `path` when it is missing: "run the <stage> stage first".
void require_stage_output(const std::string& path, const char* stage);

}  // namespace rangecal
