#pragma once
// Byte access shared by the binary autopilot-log readers (PX4 ULog, ArduPilot DataFlash): both
// formats store integers and IEEE 754 floats little-endian ("ULog File Format": "little endian
// memory layout for all binary types"; DataFlash: the packed C structs of the ARM/x86 autopilots
// that write it). The readers check every length against the bytes left before calling these, so
// the readers here take a pointer to bytes known to be there. Text taken from a binary file (topic,
// field and message names) is quoted through `quote_log_text` before it goes into a message, so an
// error never echoes raw binary bytes to a terminal.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace rangecal {

/// Little-endian unsigned integer of `N` bytes (N ≤ 8) at p.
template <int N>
std::uint64_t load_le_unsigned(const char* p) {
  std::uint64_t v = 0;
  for (int i = N - 1; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(p[i]);
  return v;
}
inline std::uint8_t load_u8(const char* p) {
  return static_cast<std::uint8_t>(*p);
}
inline std::uint16_t load_u16(const char* p) {
  return static_cast<std::uint16_t>(load_le_unsigned<2>(p));
}
inline std::uint32_t load_u32(const char* p) {
  return static_cast<std::uint32_t>(load_le_unsigned<4>(p));
}
inline std::uint64_t load_u64(const char* p) {
  return load_le_unsigned<8>(p);
}
/// Two's-complement readings of the same bytes (well defined since C++20, and what every C++17
/// compiler we build with does for these conversions).
inline std::int8_t load_i8(const char* p) {
  return static_cast<std::int8_t>(load_u8(p));
}
inline std::int16_t load_i16(const char* p) {
  return static_cast<std::int16_t>(load_u16(p));
}
inline std::int32_t load_i32(const char* p) {
  return static_cast<std::int32_t>(load_u32(p));
}
inline std::int64_t load_i64(const char* p) {
  return static_cast<std::int64_t>(load_u64(p));
}
/// IEEE 754 binary32 / binary64 from their little-endian bit patterns.
inline float load_f32(const char* p) {
  const std::uint32_t bits = load_u32(p);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}
inline double load_f64(const char* p) {
  const std::uint64_t bits = load_u64(p);
  double d;
  std::memcpy(&d, &bits, sizeof d);
  return d;
}

/// `text` for a message: printable ASCII kept, any other byte written as `\xNN`, cut after
/// `max_chars` input bytes (with "…").
inline std::string quote_log_text(std::string_view text, std::size_t max_chars = 64) {
  static const char* hex = "0123456789abcdef";
  std::string r;
  for (std::size_t i = 0; i < text.size() && i < max_chars; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      r += static_cast<char>(c);
    } else {
      r += "\\x";
      r += hex[c >> 4];
      r += hex[c & 15];
    }
  }
  if (text.size() > max_chars) r += "…";
  return r;
}

/// `text` up to its first NUL (fixed-size C string fields are NUL-padded).
inline std::string_view until_nul(std::string_view text) {
  const std::size_t z = text.find('\0');
  return z == std::string_view::npos ? text : text.substr(0, z);
}

}  // namespace rangecal
