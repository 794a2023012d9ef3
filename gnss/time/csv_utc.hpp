#pragma once
// The UTC cell of a CSV record: ISO 8601 UTC as parse_iso8601_utc reads it (docs/conventions.md
// "Time"), or rangecal::Error (kind input) naming the file, the line and the column, with the
// cell's text and why it is not a UTC time. Every table with a `utc` column reads it here, so its
// rule and its message are written once. It sits in gnss/time beside the parser rather than on
// config's CsvTable, which is the layer below and knows no time.
#include <cstddef>

#include "config/csv_table.hpp"
#include "gnss/time/utc_time.hpp"

namespace rangecal {

/// The UTC instant in column `col` of record `r` of `t`.
UtcTime csv_utc(const CsvTable& t, const CsvRecord& r, std::size_t col);

}  // namespace rangecal
