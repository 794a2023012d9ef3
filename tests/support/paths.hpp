#pragma once
// Paths the tests need: the real data samples, the source tree, the built CLI, scratch dirs.
#include <filesystem>
#include <string>

namespace rangecal::test {

/// tests/data/external/<rel>: the real samples the tests read, kept in the repository so that a
/// clone needs nothing beside it (tests/data/external/README.md gives origins and licences).
inline std::filesystem::path external(const std::string& rel) {
  return std::filesystem::path(RANGECAL_EXTERNAL_DIR) / rel;
}
/// The repository root (for config/examples/ and the like).
inline std::filesystem::path source_dir() {
  return RANGECAL_SOURCE_DIR;
}
/// The built `rangecal` executable.
inline std::filesystem::path rangecal_binary() {
  return RANGECAL_BINARY;
}

/// A fresh, empty scratch directory unique to the calling test (removed and recreated); removed
/// again when the test process exits unless RANGECAL_KEEP_SCRATCH is set.
std::filesystem::path scratch_dir(const std::string& name);

/// Result of running the CLI: exit code and captured stdout / stderr.
struct CliResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};
/// Runs `rangecal <args>` (args already shell-quoted where needed) and captures its output.
CliResult run_cli(const std::string& args);

/// Writes `content` to `path` (creating parent folders); for building bad-input cases.
void write_text(const std::filesystem::path& path, const std::string& content);
/// Reads a whole file; throws std::runtime_error when it cannot be opened (a test must not pass
/// on an empty read).
std::string read_text(const std::filesystem::path& path);

}  // namespace rangecal::test
