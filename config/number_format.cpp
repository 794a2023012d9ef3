#include "config/number_format.hpp"

#include <fmt/printf.h>

#include <cmath>

namespace rangecal {

std::string format_number(const char* format, double value) {
  return fmt::sprintf(format, value);
}

std::string format_finite(const char* format, double value) {
  return std::isfinite(value) ? format_number(format, value) : std::string();
}

}  // namespace rangecal
