#include "config/number_format.hpp"

#include <cmath>
#include <cstdio>

namespace rangecal {

std::string format_number(const char* format, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, value);
  return buf;
}

std::string format_finite(const char* format, double value) {
  return std::isfinite(value) ? format_number(format, value) : std::string();
}

}  // namespace rangecal
