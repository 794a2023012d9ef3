#include "gnss/time/csv_utc.hpp"

#include <optional>
#include <string>

#include "config/error.hpp"

namespace rangecal {

UtcTime csv_utc(const CsvTable& t, const CsvRecord& r, std::size_t col) {
  std::string why;
  const std::optional<UtcTime> utc = parse_iso8601_utc(t.text(r, col), &why);
  if (!utc) throw_input_error(t.path, r.line, t.header[col], "'" + t.text(r, col) + "': " + why);
  return *utc;
}

}  // namespace rangecal
