#include "gnss/formats/file_facts.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "config/error.hpp"

namespace rangecal {

std::optional<double> median_rate_hz(const std::vector<UtcTime>& stamps) {
  if (stamps.size() < 2) return std::nullopt;
  std::vector<std::int64_t> d;
  d.reserve(stamps.size() - 1);
  for (std::size_t i = 1; i < stamps.size(); ++i) d.push_back(stamps[i].ns - stamps[i - 1].ns);
  const auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
  std::nth_element(d.begin(), mid, d.end());
  if (*mid <= 0) return std::nullopt;
  return 1e9 / static_cast<double>(*mid);
}

std::uint64_t file_size_bytes(const std::string& path) {
  std::error_code ec;
  const auto n = std::filesystem::file_size(path, ec);
  if (ec) throw_input_error(path, 0, "", "cannot read the file: " + ec.message());
  return static_cast<std::uint64_t>(n);
}

}  // namespace rangecal
