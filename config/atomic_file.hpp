#pragma once
// Outputs are written atomically (docs/outputs.md): the content goes to a temporary file in the same
// folder, which is then renamed over the target, so a killed run never leaves a half-written file.
#include <cstddef>
#include <string>

namespace rangecal {

/// Writes `content` to `path` atomically, creating parent folders. Throws rangecal::Error (input)
/// naming the path when the folder or file cannot be written.
void write_file_atomic(const std::string& path, const std::string& content);

/// Removes, under `folder` (recursively), the temporary files `<name>.tmp.<pid>` of write_file_atomic
/// whose process is no longer alive (a run killed between writing and renaming). Returns how many
/// went. A missing folder is not an error.
std::size_t remove_dead_temp_files(const std::string& folder);

}  // namespace rangecal
