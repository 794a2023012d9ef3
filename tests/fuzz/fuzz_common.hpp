#pragma once
// Shared by the libFuzzer targets (tests/fuzz/fuzz_*.cpp; docs/reliability.md "Fuzzing").
// A target hands the fuzzer's bytes to one parser. rangecal::Error is the expected answer to bad
// input and is caught; anything else — another exception escaping, a crash, a sanitizer report, a
// timeout or running out of memory — reaches libFuzzer and is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "config/error.hpp"

namespace rangecal::fuzz {

inline std::string as_string(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Runs `parse`; a rangecal::Error is the expected outcome of bad input. Its message must still
/// be formed without fault (what() is read so that a sanitizer sees the formatting).
template <class F>
void expect_parse_or_error(F&& parse) {
  try {
    parse();
  } catch (const rangecal::Error& e) {
    volatile std::size_t n = std::string_view(e.what()).size();
    (void)n;
  }
}

/// A per-process scratch file for the readers that only open a path. Lives in the temporary
/// directory (TMPDIR; run_fuzz.sh points it into the build folder) and is removed when the process
/// exits normally.
class ScratchFile {
 public:
  explicit ScratchFile(const std::string& name_with_extension) {
    path_ = (std::filesystem::temp_directory_path() /
             ("rangecal-fuzz-" + std::to_string(::getpid()) + "-" + name_with_extension))
                .string();
  }
  ~ScratchFile() {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  const std::string& write(std::string_view bytes) const {
    std::ofstream f(path_, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path_;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace rangecal::fuzz
