#pragma once
// The one text formatting path: every number, table cell and deterministic text file is formatted
// by {fmt} (https://fmt.dev), which never consults the locale (the decimal point is always '.'),
// so the same number gives the same bytes everywhere. Code that writes many numbers calls
// fmt::format / fmt::format_to with a compile-time checked format string; format_number is for
// one number whose printf conversion is chosen at run time or shared between call sites.
//
// {fmt}'s "{:.4f}" prints a finite double exactly as printf's "%.4f" does (both round the exact
// binary value correctly; tests/unit/config/number_format_test.cpp compares them over many
// values). One difference matters: with a width, {fmt} 9 left-aligns "nan" and "inf" where printf
// right-aligns them, so a width on a number that may be non-finite is written with an explicit
// '>' ("{:>8.3f}").
#include <fmt/format.h>

#include <string>

namespace rangecal {

/// `value` printed with the printf conversion `format` (one double conversion such as "%.3g",
/// "%.4f", "%+.2e"), formatted by {fmt}'s printf implementation: the same bytes as std::snprintf.
std::string format_number(const char* format, double value);

/// As format_number, but "" for NaN or infinity (an empty CSV field, a blank table cell).
std::string format_finite(const char* format, double value);

}  // namespace rangecal
