#include "support/pos_rows.hpp"

#include <sstream>

#include "support/paths.hpp"

namespace rangecal::test {

std::vector<std::vector<std::string>> pos_rows(const std::filesystem::path& path) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(read_text(path));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '%') continue;
    std::istringstream fields(line);
    std::vector<std::string> row;
    std::string w;
    while (fields >> w) row.push_back(w);
    rows.push_back(row);
  }
  return rows;
}

}  // namespace rangecal::test
