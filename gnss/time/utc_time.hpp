#pragma once
// Time as rangecal carries it (docs/conventions.md): UTC as integer nanoseconds since 1970-01-01T00:00:00Z,
// never a bare double. GPS time (GPST) is a separate type, integer nanoseconds since the GPS
// epoch 1980-01-06T00:00:00 (GPST), converted to UTC with the full leap-second table
// (GPS−UTC = 0 s in 1980 … 18 s since 2017-01-01). Leap seconds themselves are not representable
// in UTC here (as in POSIX time): instants inside an inserted leap second map onto its end.
#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace rangecal {

constexpr std::int64_t kNsPerSecond = 1'000'000'000;

/// An instant in UTC: ns since the Unix epoch, leap seconds not counted (POSIX scale).
struct UtcTime {
  std::int64_t ns = 0;
  friend bool operator<(UtcTime a, UtcTime b) { return a.ns < b.ns; }
  friend bool operator<=(UtcTime a, UtcTime b) { return a.ns <= b.ns; }
  friend bool operator>(UtcTime a, UtcTime b) { return a.ns > b.ns; }
  friend bool operator>=(UtcTime a, UtcTime b) { return a.ns >= b.ns; }
  friend bool operator==(UtcTime a, UtcTime b) { return a.ns == b.ns; }
  friend bool operator!=(UtcTime a, UtcTime b) { return a.ns != b.ns; }
};

/// An instant in GPS time: ns since 1980-01-06T00:00:00 GPST (continuous, no leap seconds).
struct GpsTime {
  std::int64_t ns = 0;
  friend bool operator==(GpsTime a, GpsTime b) { return a.ns == b.ns; }
};

/// Seconds (as double, for arithmetic on short intervals only) from a to b: b − a.
inline double seconds_between(UtcTime a, UtcTime b) {
  return static_cast<double>(b.ns - a.ns) * 1e-9;
}
inline UtcTime add_seconds(UtcTime t, double s) {
  return UtcTime{t.ns + static_cast<std::int64_t>(s * 1e9 + (s >= 0 ? 0.5 : -0.5))};
}

/// Days since 1970-01-01 of a proleptic Gregorian date (month 1–12, day 1–31).
std::int64_t days_from_civil(int year, int month, int day);
/// True when y-m-d is a valid Gregorian date.
bool valid_civil_date(int year, int month, int day);
/// The calendar years rangecal accepts in any time stamp. int64 nanoseconds since 1970 reach
/// 2262-04-11; the span stops well before so that sums of a time and an offset cannot overflow.
constexpr int kFirstSupportedYear = 1970;
constexpr int kLastSupportedYear = 2200;
inline bool supported_civil_year(int year) {
  return year >= kFirstSupportedYear && year <= kLastSupportedYear;
}
/// "year Y is outside the supported span 1970-2200" for messages.
std::string unsupported_year_reason(int year);

/// UTC instant from calendar fields; `nanos` is within the second. The year must be a supported
/// one (callers check supported_civil_year and report the field).
UtcTime utc_from_civil(int year, int month, int day, int hour, int minute, int second, std::int64_t nanos);

/// The n (≤ 9) decimal digits of s at pos as an int; false when any is not a digit or s is short.
bool fixed_digits(std::string_view s, std::size_t pos, std::size_t n, int* out);
/// Parses ISO 8601 UTC as used in our CSVs: `YYYY-MM-DDThh:mm:ss[.fffffffff]Z` (1–9 fraction
/// digits; a space is accepted instead of `T`). Returns nullopt with `why` set on failure.
std::optional<UtcTime> parse_iso8601_utc(std::string_view text, std::string* why = nullptr);
/// Formats as `YYYY-MM-DDThh:mm:ss.fffffffffZ` with `digits` fraction digits (0–9, truncating).
std::string format_iso8601_utc(UtcTime t, int digits = 9);

/// Parses a decimal number of seconds exactly into ns ("217331.000" → 217331000000000), up to 9
/// fraction digits; nullopt when not a plain decimal or beyond an int64 of ns (~292 years).
std::optional<std::int64_t> parse_decimal_seconds_ns(std::string_view text);

/// GPS−UTC in whole seconds at a UTC instant (0 before 1981-07-01, 18 since 2017-01-01).
int gps_minus_utc_seconds_at_utc(UtcTime t);
/// GPS−UTC in whole seconds at a GPS instant.
int gps_minus_utc_seconds_at_gps(GpsTime t);

UtcTime gps_to_utc(GpsTime t);
GpsTime utc_to_gps(UtcTime t);

/// GPS instant from week number (continuous, not modulo 1024) and seconds of week in ns.
GpsTime gps_from_week_tow(int week, std::int64_t tow_ns);
/// The GPS calendar reading (the calendar as if GPST were UTC-without-leaps) → GpsTime.
GpsTime gps_from_civil(int year, int month, int day, int hour, int minute, int second, std::int64_t nanos);

/// Index of the element of `items` (in increasing order of time_of(item), a UtcTime) nearest to
/// `t`; a tie goes to the later element; items.size() when `items` is empty. O(log n).
template <class Items, class TimeOf>
std::size_t nearest_in_time(const Items& items, UtcTime t, TimeOf time_of) {
  const auto first = std::begin(items), last = std::end(items);
  const auto it = std::lower_bound(first, last, t, [&](const auto& x, UtcTime u) { return time_of(x) < u; });
  const std::size_t hi = static_cast<std::size_t>(it - first), n = static_cast<std::size_t>(last - first);
  if (hi == n) return n == 0 ? 0 : n - 1;
  if (hi == 0) return 0;
  return t.ns - time_of(*(it - 1)).ns < time_of(*it).ns - t.ns ? hi - 1 : hi;
}

}  // namespace rangecal
