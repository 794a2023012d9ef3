#include "gnss/time/utc_time.hpp"

#include <array>
#include <limits>

#include "config/number_format.hpp"

namespace rangecal {
namespace {

// Unix time of the GPS epoch 1980-01-06T00:00:00 (GPS−UTC was 0 then).
constexpr std::int64_t kGpsEpochUnixS = 315964800;

// Leap-second table: UTC instant (Unix s) from which GPS−UTC takes the given value. Source: IERS
// Bulletin C / RTKLIB rtkcmn.c leaps[]; no leap second has been inserted since 2017-01-01.
struct Leap {
  std::int64_t utc_unix_s;
  int gps_minus_utc;
};
constexpr std::array<Leap, 18> kLeaps = {{
    {362793600, 1},    // 1981-07-01
    {394329600, 2},    // 1982-07-01
    {425865600, 3},    // 1983-07-01
    {489024000, 4},    // 1985-07-01
    {567993600, 5},    // 1988-01-01
    {631152000, 6},    // 1990-01-01
    {662688000, 7},    // 1991-01-01
    {709948800, 8},    // 1992-07-01
    {741484800, 9},    // 1993-07-01
    {773020800, 10},   // 1994-07-01
    {820454400, 11},   // 1996-01-01
    {867715200, 12},   // 1997-07-01
    {915148800, 13},   // 1999-01-01
    {1136073600, 14},  // 2006-01-01
    {1230768000, 15},  // 2009-01-01
    {1341100800, 16},  // 2012-07-01
    {1435708800, 17},  // 2015-07-01
    {1483228800, 18},  // 2017-01-01
}};

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  return a / b - ((a % b != 0) && ((a < 0) != (b < 0)));
}

}  // namespace

bool fixed_digits(std::string_view s, std::size_t pos, std::size_t n, int* out) {
  if (pos + n > s.size() || n > 9) return false;
  int v = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const char c = s[pos + i];
    if (c < '0' || c > '9') return false;
    v = v * 10 + (c - '0');
  }
  *out = v;
  return true;
}

std::int64_t days_from_civil(int y, int m, int d) {
  // H. Hinnant's algorithm, proleptic Gregorian.
  y -= m <= 2;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

bool valid_civil_date(int y, int m, int d) {
  if (m < 1 || m > 12 || d < 1) return false;
  static constexpr int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
  return d <= kDays[m - 1] + (m == 2 && leap ? 1 : 0);
}

std::string unsupported_year_reason(int year) {
  return "year " + std::to_string(year) + " is outside the supported span " +
         std::to_string(kFirstSupportedYear) + "-" + std::to_string(kLastSupportedYear);
}

UtcTime utc_from_civil(int year, int month, int day, int hour, int minute, int second, std::int64_t nanos) {
  const std::int64_t s = days_from_civil(year, month, day) * 86400 + hour * 3600 + minute * 60 + second;
  return UtcTime{s * kNsPerSecond + nanos};
}

std::optional<std::int64_t> parse_decimal_seconds_ns(std::string_view t) {
  if (t.empty()) return std::nullopt;
  bool neg = false;
  std::size_t i = 0;
  if (t[0] == '-' || t[0] == '+') {
    neg = t[0] == '-';
    i = 1;
  }
  std::int64_t whole = 0;
  std::size_t nwhole = 0;
  for (; i < t.size() && t[i] >= '0' && t[i] <= '9'; ++i, ++nwhole) {
    if (nwhole > 11) return std::nullopt;
    whole = whole * 10 + (t[i] - '0');
  }
  std::int64_t frac = 0;
  int nfrac = 0;
  if (i < t.size() && t[i] == '.') {
    ++i;
    for (; i < t.size() && t[i] >= '0' && t[i] <= '9'; ++i) {
      if (nfrac >= 9) return std::nullopt;
      frac = frac * 10 + (t[i] - '0');
      ++nfrac;
    }
  }
  if (i != t.size() || (nwhole == 0 && nfrac == 0)) return std::nullopt;
  // Up to 12 digits fit the accumulator, but whole · 10⁹ + frac must fit an int64 too (~292 years
  // of seconds); anything larger is no time of day or of week.
  constexpr std::int64_t kMaxWholeSeconds =
      (std::numeric_limits<std::int64_t>::max() - 999999999) / kNsPerSecond;
  if (whole > kMaxWholeSeconds) return std::nullopt;
  for (int k = nfrac; k < 9; ++k) frac *= 10;
  const std::int64_t ns = whole * kNsPerSecond + frac;
  return neg ? -ns : ns;
}

std::optional<UtcTime> parse_iso8601_utc(std::string_view s, std::string* why) {
  auto fail = [&](const char* reason) -> std::optional<UtcTime> {
    if (why) *why = reason;
    return std::nullopt;
  };
  int Y, M, D, h, m, sec;
  if (!fixed_digits(s, 0, 4, &Y) || s.size() < 20 || s[4] != '-' || !fixed_digits(s, 5, 2, &M) ||
      s[7] != '-' || !fixed_digits(s, 8, 2, &D) || (s[10] != 'T' && s[10] != ' ') ||
      !fixed_digits(s, 11, 2, &h) || s[13] != ':' || !fixed_digits(s, 14, 2, &m) || s[16] != ':' ||
      !fixed_digits(s, 17, 2, &sec))
    return fail("not ISO 8601 UTC (expected YYYY-MM-DDThh:mm:ss[.fffffffff]Z)");
  if (!valid_civil_date(Y, M, D)) return fail("invalid calendar date");
  if (!supported_civil_year(Y)) {
    if (why) *why = unsupported_year_reason(Y);
    return std::nullopt;
  }
  if (h > 23 || m > 59 || sec > 59) return fail("invalid time of day (leap second 60 is not accepted)");
  std::size_t i = 19;
  std::int64_t frac = 0;
  int nfrac = 0;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && s[i] >= '0' && s[i] <= '9') {
      if (nfrac == 9) return fail("more than 9 fraction digits");
      frac = frac * 10 + (s[i] - '0');
      ++nfrac;
      ++i;
    }
    if (nfrac == 0) return fail("no digits after the decimal point");
  }
  if (i >= s.size() || s[i] != 'Z') return fail("missing 'Z' (times must be UTC)");
  if (i + 1 != s.size()) return fail("trailing characters after 'Z'");
  for (int k = nfrac; k < 9; ++k) frac *= 10;
  return utc_from_civil(Y, M, D, h, m, sec, frac);
}

std::string format_iso8601_utc(UtcTime t, int ndigits) {
  const std::int64_t s = floor_div(t.ns, kNsPerSecond);
  std::int64_t nanos = t.ns - s * kNsPerSecond;
  std::int64_t days = floor_div(s, 86400);
  std::int64_t sod = s - days * 86400;
  // civil_from_days (H. Hinnant)
  days += 719468;
  const std::int64_t era = (days >= 0 ? days : days - 146096) / 146097;
  const unsigned doe = static_cast<unsigned>(days - era * 146097);
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  std::int64_t y = static_cast<std::int64_t>(yoe) + era * 400;
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const unsigned mp = (5 * doy + 2) / 153;
  const unsigned d = doy - (153 * mp + 2) / 5 + 1;
  const unsigned m = mp < 10 ? mp + 3 : mp - 9;
  y += m <= 2;
  fmt::memory_buffer buf;
  fmt::format_to(std::back_inserter(buf), "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}", y, m, d, sod / 3600,
                 sod / 60 % 60, sod % 60);
  if (ndigits > 0) {
    if (ndigits > 9) ndigits = 9;
    for (int k = ndigits; k < 9; ++k) nanos /= 10;
    fmt::format_to(std::back_inserter(buf), ".{:0{}}", nanos, ndigits);
  }
  buf.push_back('Z');
  return fmt::to_string(buf);
}

int gps_minus_utc_seconds_at_utc(UtcTime t) {
  const std::int64_t s = floor_div(t.ns, kNsPerSecond);
  int off = 0;
  for (const Leap& l : kLeaps)
    if (s >= l.utc_unix_s) off = l.gps_minus_utc;
  return off;
}

int gps_minus_utc_seconds_at_gps(GpsTime t) {
  // A table entry starts, on the GPS scale, at its UTC instant plus its new offset.
  const std::int64_t gps_unix_like = floor_div(t.ns, kNsPerSecond) + kGpsEpochUnixS;
  int off = 0;
  for (const Leap& l : kLeaps)
    if (gps_unix_like >= l.utc_unix_s + l.gps_minus_utc) off = l.gps_minus_utc;
  return off;
}

UtcTime gps_to_utc(GpsTime t) {
  return UtcTime{t.ns + kGpsEpochUnixS * kNsPerSecond -
                 static_cast<std::int64_t>(gps_minus_utc_seconds_at_gps(t)) * kNsPerSecond};
}

GpsTime utc_to_gps(UtcTime t) {
  return GpsTime{t.ns - kGpsEpochUnixS * kNsPerSecond +
                 static_cast<std::int64_t>(gps_minus_utc_seconds_at_utc(t)) * kNsPerSecond};
}

GpsTime gps_from_week_tow(int week, std::int64_t tow_ns) {
  return GpsTime{static_cast<std::int64_t>(week) * 604800 * kNsPerSecond + tow_ns};
}

GpsTime gps_from_civil(int year, int month, int day, int hour, int minute, int second, std::int64_t nanos) {
  const UtcTime as_if_utc = utc_from_civil(year, month, day, hour, minute, second, nanos);
  return GpsTime{as_if_utc.ns - kGpsEpochUnixS * kNsPerSecond};
}

}  // namespace rangecal
