#include "gnss/time/csv_utc.hpp"

#include <gtest/gtest.h>

#include "config/error.hpp"

namespace rangecal {
namespace {

TEST(CsvUtc, ReadsTheCell) {
  const CsvTable t = parse_csv("frame,utc\n1,2018-10-09T12:21:53.5Z\n", "stamps.csv");
  EXPECT_EQ(format_iso8601_utc(csv_utc(t, t.records[0], t.column("utc")), 1), "2018-10-09T12:21:53.5Z");
}

// Every reader of a utc column words the error the same way: file, line, the column's name, the
// cell's text and why it is not a UTC time.
TEST(CsvUtc, ABadCellNamesFileLineColumnTextAndWhy) {
  const CsvTable t = parse_csv("frame,utc\n1,2018-10-09T12:21:53Z\n2,2018-10-09T12:21:54.0\n", "stamps.csv");
  try {
    csv_utc(t, t.records[1], t.column("utc"));
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "stamps.csv");
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "utc");
    EXPECT_EQ(e.reason(), "'2018-10-09T12:21:54.0': missing 'Z' (times must be UTC)");
  }
}

}  // namespace
}  // namespace rangecal
