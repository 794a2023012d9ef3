#pragma once
// The data lines of an RTKLIB .pos file as plain text, for tests that check what the simulator
// wrote without the project's .pos reader or writer.
#include <filesystem>
#include <string>
#include <vector>

namespace rangecal::test {

/// The data lines of `path` (header lines starting '%' and blank lines skipped), each split on
/// whitespace.
std::vector<std::vector<std::string>> pos_rows(const std::filesystem::path& path);

}  // namespace rangecal::test
