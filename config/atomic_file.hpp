#pragma once
// Outputs are written atomically (SPEC §5): the content goes to a temporary file in the same
// folder, which is then renamed over the target, so a killed run never leaves a half-written file.
#include <string>

namespace rangecal {

/// Writes `content` to `path` atomically, creating parent folders. Throws rangecal::Error (input)
/// naming the path when the folder or file cannot be written.
void write_file_atomic(const std::string& path, const std::string& content);

}  // namespace rangecal
