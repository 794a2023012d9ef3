#pragma once
// One number formatter for messages, tables and deterministic text files: printf formatting in the
// C locale's form (the project never calls setlocale, so the decimal point is always '.'), so the
// same number gives the same bytes everywhere.
#include <string>

namespace rangecal {

/// `value` printed with the printf conversion `format` (one double conversion such as "%.3g",
/// "%.4f", "%+.2e"), at most 63 characters.
std::string format_number(const char* format, double value);

/// As format_number, but "" for NaN or infinity (an empty CSV field, a blank table cell).
std::string format_finite(const char* format, double value);

}  // namespace rangecal
