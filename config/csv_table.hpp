#pragma once
// A small CSV reader for the project's input tables (docs/formats.md): a header line naming the columns,
// then one record per line, comma separated, no quoting (none of our formats needs it). Blank
// lines and lines starting with '#' are skipped; CRLF line ends and a UTF-8 byte-order mark are
// accepted; a byte that is not UTF-8 in a record is an error naming its line and column. Every accessor that
// can fail throws rangecal::Error (kind input) naming the file, the 1-based line and the column.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rangecal {

struct CsvRecord {
  long line = 0;                    ///< 1-based line number in the file
  std::vector<std::string> fields;  ///< trimmed of surrounding blanks
};

struct CsvTable {
  std::string path;                 ///< as given, for messages
  std::vector<std::string> header;  ///< column names, trimmed
  long header_line = 0;             ///< 1-based line of the header (after blank and '#' lines)
  std::vector<CsvRecord> records;

  /// Index of column `name`; throws (line 1) when the header lacks it.
  std::size_t column(const std::string& name) const;
  /// Index of column `name`, or nullopt.
  std::optional<std::size_t> find_column(const std::string& name) const;

  const std::string& text(const CsvRecord& r, std::size_t col) const;
  /// A finite double; throws naming file, line and column otherwise.
  double number(const CsvRecord& r, std::size_t col) const;
  /// A number within [lo, hi]; throws naming file, line, column, the range and `what` it is
  /// ("ellipsoidal height, m") otherwise.
  double number_in(const CsvRecord& r, std::size_t col, double lo, double hi, const std::string& what) const;
  /// Columns (ce, cn, cu) as site ENU (m), each within the site box of config/physical_ranges.hpp.
  std::array<double, 3> site_enu(const CsvRecord& r, std::size_t ce, std::size_t cn, std::size_t cu) const;
  std::int64_t integer(const CsvRecord& r, std::size_t col) const;
};

/// Reads `path`. Throws (kind input) when the file is missing or unreadable, has no header, or a
/// record's field count differs from the header's. Reading does not require any record.
CsvTable read_csv(const std::string& path);
/// Parses CSV text already in memory; `path` is used for messages only.
CsvTable parse_csv(const std::string& text, const std::string& path);

/// Strict number parsing (whole field must be consumed, value finite). nullopt on failure.
std::optional<double> parse_double(std::string_view s);
std::optional<std::int64_t> parse_int64(std::string_view s);
/// Splits on `sep` and trims blanks around each piece.
std::vector<std::string> split_trim(std::string_view line, char sep);
std::string_view trim(std::string_view s);

/// Reads a whole file into a string; throws (kind input) naming the file when it cannot.
std::string read_file_text(const std::string& path);

}  // namespace rangecal
