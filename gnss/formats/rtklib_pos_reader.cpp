#include "gnss/formats/rtklib_pos_reader.hpp"

#include <GeographicLib/Geocentric.hpp>
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "config/text_encoding.hpp"

namespace rangecal {

const char* to_string(PosTimeSystem s) {
  switch (s) {
    case PosTimeSystem::gpst:
      return "GPST";
    case PosTimeSystem::utc:
      return "UTC";
    case PosTimeSystem::jst:
      return "JST";
  }
  return "?";
}

const char* to_string(PosTimeFormat f) {
  return f == PosTimeFormat::calendar ? "calendar" : "week/tow";
}

const char* to_string(PosPositionFormat f) {
  switch (f) {
    case PosPositionFormat::llh_deg:
      return "lat/lon/height (deg)";
    case PosPositionFormat::llh_dms:
      return "lat/lon/height (d m s)";
    case PosPositionFormat::ecef:
      return "ECEF x/y/z";
    case PosPositionFormat::enu_baseline:
      return "e/n/u baseline";
  }
  return "?";
}

namespace {

constexpr std::int64_t kJstOffsetNs = 9 * 3600 * kNsPerSecond;
constexpr std::int64_t kWeekNs = 604800 * kNsPerSecond;
constexpr std::size_t kMaxTokens = 40;

// Physical ranges of a .pos record (docs/reliability.md, "Input ranges"): a UAV flies between the
// Dead Sea and the stratosphere; RTKLIB works on baselines up to hundreds of km.
constexpr double kMinHeightM = -1000, kMaxHeightM = 20000;  // ellipsoidal height
constexpr double kMinEcefRadiusM = 6356752.0 - 22000;       // polar radius − 22 km
constexpr double kMaxEcefRadiusM = 6378137.0 + 21000;       // equatorial radius + 21 km
constexpr double kMaxBaselineM = 1.0e6;                     // |e|, |n|
constexpr double kMaxSigmaM = 1.0e4;                        // σ and signed √covariance terms
constexpr double kMaxVelocityMps = 1000;
constexpr double kMaxAgeS = 1.0e6;
constexpr double kMaxRatio = 1.0e6;
// The last GPS week of kLastSupportedYear (whole weeks from 1980-01-06 to 2200-12-31).
constexpr long long kLastSupportedGpsWeek = 11530;

// RTKLIB separates fields by blanks (default) or by the `-s` separator; blanks pad either way.
// A stray '\r' (a CRLF file converted twice, "\r\r\n") separates like a blank.
inline bool is_sep(char c) {
  return c == ' ' || c == '\t' || c == ',' || c == '\r';
}

/// Splits `s` into at most kMaxTokens tokens; returns the count (kMaxTokens + 1 means "more").
std::size_t tokenize(std::string_view s, std::array<std::string_view, kMaxTokens>& out) {
  std::size_t n = 0, i = 0;
  const std::size_t len = s.size();
  while (i < len) {
    while (i < len && is_sep(s[i])) ++i;
    if (i >= len) break;
    const std::size_t b = i;
    while (i < len && !is_sep(s[i])) ++i;
    if (n == kMaxTokens) return kMaxTokens + 1;
    out[n++] = s.substr(b, i - b);
  }
  return n;
}

std::vector<std::string> tokenize_all(std::string_view s) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_sep(s[i])) ++i;
    if (i >= s.size()) break;
    const std::size_t b = i;
    while (i < s.size() && !is_sep(s[i])) ++i;
    out.emplace_back(s.substr(b, i - b));
  }
  return out;
}

// Fast path for the plain decimals RTKLIB prints ("-8.982172753"): an integer mantissa below 2^53
// divided by an exact power of ten is one correctly rounded operation on exact operands, so it
// equals from_chars' result bit for bit. Anything else (exponents, > 15 digits) goes to from_chars.
bool plain_decimal(std::string_view t, double* v) {
  static constexpr double kPow10[] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                      1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};
  std::size_t i = 0;
  const bool neg = t[0] == '-';
  if (neg) ++i;
  std::int64_t m = 0;
  int ndig = 0, nfrac = 0;
  bool dot = false, any = false;
  for (; i < t.size(); ++i) {
    const char c = t[i];
    if (c >= '0' && c <= '9') {
      if (ndig > 0 || c != '0') ++ndig;
      if (ndig > 15) return false;
      m = m * 10 + (c - '0');
      nfrac += dot;
      any = true;
    } else if (c == '.' && !dot) {
      dot = true;
    } else {
      return false;
    }
  }
  if (!any || nfrac > 15) return false;
  const double x = static_cast<double>(m) / kPow10[nfrac];
  *v = neg ? -x : x;
  return true;
}

bool to_double(std::string_view t, double* v) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  if (plain_decimal(t, v)) return true;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), *v);
  return ec == std::errc() && p == t.data() + t.size() && std::isfinite(*v);
}

bool to_int(std::string_view t, long long* v) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), *v);
  return ec == std::errc() && p == t.data() + t.size();
}

// The time of an epoch as read ("reading"): ns on a leap-free scale since 1970 of whatever the
// file's time system is. Converted to UTC by to_utc.
UtcTime to_utc(std::int64_t reading_ns, PosTimeSystem sys) {
  switch (sys) {
    case PosTimeSystem::gpst: {
      const std::int64_t gps_epoch_unix_ns = utc_from_civil(1980, 1, 6, 0, 0, 0, 0).ns;
      return gps_to_utc(GpsTime{reading_ns - gps_epoch_unix_ns});
    }
    case PosTimeSystem::utc:
      return UtcTime{reading_ns};
    case PosTimeSystem::jst:
      return UtcTime{reading_ns - kJstOffsetNs};
  }
  return UtcTime{reading_ns};
}

struct Layout {
  std::size_t pos_tokens = 3;            // 3, or 7 for d m s (2 × 3 + height)
  std::size_t total_tokens = 0;          // per data line, time included
  std::vector<std::string> field_names;  // one per data token, for messages
};

class PosParser {
 public:
  PosParser(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  PosFile run() {
    PosFile f;
    f.path = path_;
    std::size_t pos = 0;
    long line_no = 0;
    std::string_view last_comment;
    long last_comment_line = 0;
    std::string_view ref_pos_text;
    long ref_pos_line = 0;
    bool in_data = false;
    std::array<std::string_view, kMaxTokens> tok{};
    // One epoch per line at most: reserving avoids re-copying the (large) epochs as the vector
    // grows, which dominated the ingest time of long files.
    f.epochs.reserve(static_cast<std::size_t>(std::count(text_.begin(), text_.end(), '\n')) + 1);
    while (pos < text_.size()) {
      std::size_t end = text_.find('\n', pos);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view line = text_.substr(pos, end - pos);
      pos = end + 1;
      ++line_no;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      if (!line.empty() && line.front() == '%') {
        if (!in_data) {
          last_comment = line;
          last_comment_line = line_no;
          std::string_view body = line.substr(1);
          const auto colon = body.find(':');
          if (colon != std::string_view::npos) {
            std::string_view key = trim_view(body.substr(0, colon));
            if (key == "ref pos") {
              ref_pos_text = body.substr(colon + 1);
              ref_pos_line = line_no;
            } else if (key == "program") {
              f.header.program = printable_text(trim_view(body.substr(colon + 1)));  // goes to run.json
            }
          }
        }
        continue;
      }
      if (trim_view(line).empty()) continue;
      if (!in_data) {
        if (last_comment_line == 0)
          throw_input_error(path_, line_no, "",
                            "data line before any '%' header: expected a column header line such as "
                            "'%  GPST  latitude(deg) ...'");
        parse_column_header(last_comment, last_comment_line, &f.header);
        if (ref_pos_line) f.header.ref_pos_ecef = parse_ref_pos(ref_pos_text, ref_pos_line, f.header);
        in_data = true;
      }
      const std::size_t n = tokenize(line, tok);
      if (f.epochs.empty())
        f.header.time_format =
            tok[0].find('/') != std::string_view::npos ? PosTimeFormat::calendar : PosTimeFormat::week_tow;
      f.epochs.push_back(parse_epoch(tok, n, line_no, f.header));
      if (f.epochs.size() > 1) {
        const PosEpoch& prev = f.epochs[f.epochs.size() - 2];
        const PosEpoch& cur = f.epochs.back();
        if (cur.utc <= prev.utc)
          throw_input_error(path_, line_no, time_field_,
                            "time " + format_iso8601_utc(cur.utc) + " is not after the previous epoch's " +
                                format_iso8601_utc(prev.utc) + " (line " + std::to_string(prev.line) +
                                "); epochs must be strictly increasing");
      }
    }
    if (f.epochs.empty())
      throw_input_error(path_, line_no, "epochs", "no epoch lines (the file has only a header, or is empty)");
    return f;
  }

 private:
  static std::string_view trim_view(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
  }

  [[noreturn]] void bad_header(long line, const std::string& field, const std::string& why) const {
    throw_input_error(path_, line, field, "unknown column header: " + why);
  }

  // Position format from the first column's name; then the exact expected names (alternatives per
  // column) of the fixed columns and of the optional velocity columns.
  void expected_columns(long line_no, PosHeader* h, std::vector<std::vector<std::string>>* expect,
                        std::vector<std::vector<std::string>>* vel) const {
    const std::string& first = h->columns[0];
    if (first == "latitude(deg)" || first == "latitude(d'\")") {
      h->position_format = first == "latitude(deg)" ? PosPositionFormat::llh_deg : PosPositionFormat::llh_dms;
      const std::string ang = first == "latitude(deg)" ? "(deg)" : "(d'\")";
      // RTKLIB's DMS header mislabels the n-u term `sdue(m)` (SOURCE.md §4).
      *expect = {{"latitude" + ang},
                 {"longitude" + ang},
                 {"height(m)"},
                 {"Q"},
                 {"ns"},
                 {"sdn(m)"},
                 {"sde(m)"},
                 {"sdu(m)"},
                 {"sdne(m)"},
                 {"sdeu(m)"},
                 {"sdun(m)", "sdue(m)"},
                 {"age(s)"},
                 {"ratio"}};
      *vel = {{"vn(m/s)"}, {"ve(m/s)"}, {"vu(m/s)"}, {"sdvn"}, {"sdve"},
              {"sdvu"},    {"sdvne"},   {"sdveu"},   {"sdvun"}};
    } else if (first == "x-ecef(m)") {
      h->position_format = PosPositionFormat::ecef;
      *expect = {{"x-ecef(m)"}, {"y-ecef(m)"}, {"z-ecef(m)"}, {"Q"},       {"ns"},     {"sdx(m)"}, {"sdy(m)"},
                 {"sdz(m)"},    {"sdxy(m)"},   {"sdyz(m)"},   {"sdzx(m)"}, {"age(s)"}, {"ratio"}};
      *vel = {{"vx(m/s)"}, {"vy(m/s)"}, {"vz(m/s)"}, {"sdvx"}, {"sdvy"},
              {"sdvz"},    {"sdvxy"},   {"sdvyz"},   {"sdvzx"}};
    } else if (first == "e-baseline(m)") {
      h->position_format = PosPositionFormat::enu_baseline;
      *expect = {{"e-baseline(m)"}, {"n-baseline(m)"}, {"u-baseline(m)"}, {"Q"},       {"ns"},
                 {"sde(m)"},        {"sdn(m)"},        {"sdu(m)"},        {"sden(m)"}, {"sdnu(m)"},
                 {"sdue(m)"},       {"age(s)"},        {"ratio"}};
      // RTKLIB 2.4.3 writes no velocity for ENU; demo5 prints 9 velocity names but no values.
      *vel = {{"ve(m/s)"}, {"vn(m/s)"}, {"vu(m/s)"}, {"sdve"}, {"sdvn"},
              {"sdvu"},    {"sdven"},   {"sdvnu"},   {"sdvue"}};
    } else {
      bad_header(line_no, first,
                 "position column '" + first +
                     "' is none of latitude(deg), latitude(d'\"), x-ecef(m), e-baseline(m)");
    }
  }

  // The data line's token layout and the field name of each token (for messages).
  void set_layout(const PosHeader& h, const std::string& ts, std::size_t ncols) {
    const auto& cols = h.columns;
    // d m s: 3 tokens for each angle, then the height.
    layout_.pos_tokens = h.position_format == PosPositionFormat::llh_dms ? 7 : 3;
    layout_.total_tokens = 2 + layout_.pos_tokens + (ncols - 3);
    layout_.field_names.clear();
    layout_.field_names.push_back(ts + " (date or week)");
    layout_.field_names.push_back(ts + " (time or tow)");
    if (h.position_format == PosPositionFormat::llh_dms) {
      for (const char* a : {"latitude", "longitude"})
        for (const char* p : {" degrees", " minutes", " seconds"})
          layout_.field_names.push_back(std::string(a) + p);
      layout_.field_names.push_back(cols[2]);
    } else {
      for (std::size_t i = 0; i < 3; ++i) layout_.field_names.push_back(cols[i]);
    }
    for (std::size_t i = 3; i < ncols; ++i) layout_.field_names.push_back(cols[i]);
  }

  // The column header: `%  GPST  latitude(deg) longitude(deg) height(m) Q ns sdn(m) ...`.
  void parse_column_header(std::string_view line, long line_no, PosHeader* h) {
    const std::vector<std::string> words = tokenize_all(line.substr(1));
    if (words.empty()) bad_header(line_no, "", "the last '%' line before the data is empty");
    const std::string& ts = words[0];
    if (ts == "GPST")
      h->time_system = PosTimeSystem::gpst;
    else if (ts == "UTC")
      h->time_system = PosTimeSystem::utc;
    else if (ts == "JST")
      h->time_system = PosTimeSystem::jst;
    else
      bad_header(line_no, ts,
                 "first word '" + ts +
                     "' of the last '%' line before the data is not a time system (GPST, UTC or JST)");
    time_field_ = ts;
    h->column_header_line = line_no;
    h->columns.assign(words.begin() + 1, words.end());
    if (h->columns.empty()) bad_header(line_no, ts, "no column names after the time system");

    std::vector<std::vector<std::string>> expect;  // alternatives per column
    std::vector<std::vector<std::string>> vel;
    expected_columns(line_no, h, &expect, &vel);
    const auto& cols = h->columns;
    auto matches = [](const std::string& name, const std::vector<std::string>& alts) {
      for (const auto& a : alts)
        if (name == a) return true;
      return false;
    };
    for (std::size_t i = 0; i < expect.size(); ++i) {
      if (i >= cols.size()) bad_header(line_no, expect[i][0], "column '" + expect[i][0] + "' is missing");
      if (!matches(cols[i], expect[i]))
        bad_header(
            line_no, cols[i],
            "column " + std::to_string(i + 2) + " is '" + cols[i] + "', expected '" + expect[i][0] + "'");
    }
    std::size_t ncols = expect.size();
    if (cols.size() > expect.size()) {
      if (cols.size() != expect.size() + vel.size())
        bad_header(line_no, cols[expect.size()],
                   "unexpected column '" + cols[expect.size()] +
                       "' after 'ratio' (only the 9 velocity columns "
                       "may follow)");
      for (std::size_t i = 0; i < vel.size(); ++i)
        if (!matches(cols[expect.size() + i], vel[i]))
          bad_header(line_no, cols[expect.size() + i],
                     "velocity column is '" + cols[expect.size() + i] + "', expected '" + vel[i][0] + "'");
      // For ENU the names are demo5's quirk (names without values): the data has none.
      if (h->position_format != PosPositionFormat::enu_baseline) {
        h->has_velocity = true;
        ncols = cols.size();
      }
    }
    set_layout(*h, ts, ncols);
  }

  std::optional<Eigen::Vector3d> parse_ref_pos(std::string_view text, long line_no,
                                               const PosHeader& h) const {
    const std::vector<std::string> t = tokenize_all(text);
    const bool dms = h.position_format == PosPositionFormat::llh_dms;
    const std::size_t want = dms ? 7 : 3;
    if (t.size() != want)
      throw_input_error(path_, line_no, "ref pos",
                        "expected " + std::to_string(want) + " numbers, found " + std::to_string(t.size()));
    std::array<double, 7> v{};
    for (std::size_t i = 0; i < want; ++i)
      if (!to_double(t[i], &v[i]))
        throw_input_error(path_, line_no, "ref pos", "'" + t[i] + "' is not a number");
    if (h.position_format == PosPositionFormat::ecef) {
      const Eigen::Vector3d x(v[0], v[1], v[2]);
      if (!(x.norm() >= kMinEcefRadiusM && x.norm() <= kMaxEcefRadiusM))
        throw_input_error(path_, line_no, "ref pos", "ECEF position is not near the Earth's surface");
      return x;
    }
    double lat = v[0], lon = v[1], hgt = v[2];
    if (dms) {
      lat = dms_value(t[0], v[0], v[1], v[2]);
      lon = dms_value(t[3], v[3], v[4], v[5]);
      hgt = v[6];
    }
    if (std::abs(lat) > 90 || std::abs(lon) > 180)
      throw_input_error(path_, line_no, "ref pos", "latitude/longitude out of range");
    if (hgt < kMinHeightM || hgt > kMaxHeightM)
      throw_input_error(path_, line_no, "ref pos", "height is outside [-1000, 20000] m");
    Eigen::Vector3d x;
    GeographicLib::Geocentric::WGS84().Forward(lat, lon, hgt, x[0], x[1], x[2]);
    return x;
  }

  // d m s with the sign on the degrees token only (RTKLIB prints `-0` for −1° < value < 0).
  static double dms_value(std::string_view deg_token, double d, double m, double s) {
    const double mag = std::abs(d) + m / 60.0 + s / 3600.0;
    return (!deg_token.empty() && deg_token.front() == '-') ? -mag : mag;
  }

  [[noreturn]] void bad_field(long line, std::size_t idx, std::string_view token,
                              const std::string& why) const {
    throw_input_error(path_, line, layout_.field_names[idx], "'" + std::string(token) + "' " + why);
  }

  double num(const std::array<std::string_view, kMaxTokens>& tok, std::size_t i, long line) const {
    double v;
    if (!to_double(tok[i], &v)) bad_field(line, i, tok[i], "is not a number");
    return v;
  }

  double sd(const std::array<std::string_view, kMaxTokens>& tok, std::size_t i, long line) const {
    const double v = num(tok, i, line);
    if (v < 0) bad_field(line, i, tok[i], "is negative (a standard deviation must be >= 0)");
    if (v > kMaxSigmaM)
      bad_field(line, i, tok[i], "is above " + format_number("%.10g", kMaxSigmaM) + " (not a GNSS σ)");
    return v;
  }

  // A number within [lo, hi]; `what` says what the range is.
  double num_in(const std::array<std::string_view, kMaxTokens>& tok, std::size_t i, long line, double lo,
                double hi, const std::string& what) const {
    const double v = num(tok, i, line);
    if (v < lo || v > hi)
      bad_field(line, i, tok[i],
                "is outside [" + format_number("%.10g", lo) + ", " + format_number("%.10g", hi) + "] (" +
                    what + ")");
    return v;
  }

  // Signed square root of a covariance (RTKLIB sqvar): c = sign(v)·v².
  static double cov_from_signed_sqrt(double v) { return v < 0 ? -v * v : v * v; }

  std::int64_t parse_time_reading(const std::array<std::string_view, kMaxTokens>& tok, long line,
                                  PosTimeFormat fmt) const {
    const std::string_view a = tok[0], b = tok[1];
    if (fmt == PosTimeFormat::calendar) {
      int Y, M, D, hh, mm;
      if (a.size() != 10 || !fixed_digits(a, 0, 4, &Y) || a[4] != '/' || !fixed_digits(a, 5, 2, &M) ||
          a[7] != '/' || !fixed_digits(a, 8, 2, &D))
        bad_field(line, 0, a, "is not a date yyyy/mm/dd (the first epoch line used calendar time)");
      if (!valid_civil_date(Y, M, D)) bad_field(line, 0, a, "is not a valid calendar date");
      if (!supported_civil_year(Y))
        bad_field(line, 0, a,
                  "is a date outside the supported years " + std::to_string(kFirstSupportedYear) + "-" +
                      std::to_string(kLastSupportedYear));
      if (b.size() < 8 || !fixed_digits(b, 0, 2, &hh) || b[2] != ':' || !fixed_digits(b, 3, 2, &mm) ||
          b[5] != ':')
        bad_field(line, 1, b, "is not a time of day hh:mm:ss.sss");
      const auto sec = parse_decimal_seconds_ns(b.substr(6));
      if (!sec || *sec < 0 || *sec >= 60 * kNsPerSecond || b[6] == '-' || b[6] == '+' || hh > 23 || mm > 59)
        bad_field(line, 1, b, "is not a valid time of day hh:mm:ss.sss");
      return utc_from_civil(Y, M, D, hh, mm, 0, 0).ns + *sec;
    }
    long long week;
    if (!to_int(a, &week) || week < 0)
      bad_field(line, 0, a, "is not a GPS week number (the first epoch line used week/tow time)");
    if (week > kLastSupportedGpsWeek)
      bad_field(line, 0, a,
                "is a GPS week after " + std::to_string(kLastSupportedGpsWeek) + " (" +
                    unsupported_year_reason(kLastSupportedYear + 1) + ")");
    const auto tow = parse_decimal_seconds_ns(b);
    if (!tow || *tow < 0 || *tow >= kWeekNs) bad_field(line, 1, b, "is not a time of week in [0, 604800) s");
    const std::int64_t gps_epoch_unix_ns = utc_from_civil(1980, 1, 6, 0, 0, 0, 0).ns;
    return gps_epoch_unix_ns + static_cast<std::int64_t>(week) * kWeekNs + *tow;
  }

  void check_field_count(std::size_t n, long line) const {
    if (n < layout_.total_tokens)
      throw_input_error(path_, line, layout_.field_names[n],
                        "truncated line: expected " + std::to_string(layout_.total_tokens) +
                            " fields, found " + std::to_string(n));
    if (n > layout_.total_tokens)
      throw_input_error(path_, line, "",
                        "expected " + std::to_string(layout_.total_tokens) + " fields, found " +
                            (n > kMaxTokens ? "more than " + std::to_string(kMaxTokens) : std::to_string(n)) +
                            " (extra fields after '" + layout_.field_names.back() + "')");
  }

  // The position tokens from token 2 on, into e.position; returns the index of the next token.
  std::size_t parse_position(const std::array<std::string_view, kMaxTokens>& tok, long line,
                             const PosHeader& h, PosEpoch* e) const {
    std::size_t i = 2;
    if (h.position_format == PosPositionFormat::llh_dms) {
      double v[6];
      for (int k = 0; k < 6; ++k) v[k] = num(tok, i + k, line);
      for (int k : {1, 2, 4, 5})
        if (v[k] < 0 || v[k] >= 60) bad_field(line, i + k, tok[i + k], "is not in [0, 60)");
      e->position =
          Eigen::Vector3d(dms_value(tok[i], v[0], v[1], v[2]), dms_value(tok[i + 3], v[3], v[4], v[5]), 0);
      i += 6;
      e->position[2] = num_in(tok, i++, line, kMinHeightM, kMaxHeightM, "ellipsoidal height, m");
    } else if (h.position_format == PosPositionFormat::llh_deg) {
      for (int k = 0; k < 2; ++k) e->position[k] = num(tok, i++, line);
      e->position[2] = num_in(tok, i++, line, kMinHeightM, kMaxHeightM, "ellipsoidal height, m");
    } else if (h.position_format == PosPositionFormat::enu_baseline) {
      for (int k = 0; k < 2; ++k)
        e->position[k] = num_in(tok, i++, line, -kMaxBaselineM, kMaxBaselineM, "baseline component, m");
      e->position[2] = num_in(tok, i++, line, kMinHeightM - kMaxHeightM, kMaxHeightM - kMinHeightM,
                              "up baseline component, m");
    } else {
      for (int k = 0; k < 3; ++k)
        e->position[k] = num_in(tok, i++, line, -kMaxEcefRadiusM, kMaxEcefRadiusM, "ECEF coordinate, m");
      const double r = e->position.norm();
      if (r < kMinEcefRadiusM || r > kMaxEcefRadiusM)
        bad_field(line, 2, tok[2],
                  "starts an ECEF position " + format_number("%.10g", r) +
                      " m from the Earth's centre, outside [" + format_number("%.10g", kMinEcefRadiusM) +
                      ", " + format_number("%.10g", kMaxEcefRadiusM) +
                      "] (does the column header match the columns?)");
    }
    if (h.position_format == PosPositionFormat::llh_deg || h.position_format == PosPositionFormat::llh_dms) {
      if (std::abs(e->position[0]) > 90) bad_field(line, 2, tok[2], "latitude is outside [-90, 90]");
      if (std::abs(e->position[1]) > 180)
        bad_field(line, h.position_format == PosPositionFormat::llh_dms ? 5 : 3,
                  tok[h.position_format == PosPositionFormat::llh_dms ? 5 : 3],
                  "longitude is outside [-180, 180]");
    }
    return i;
  }

  // Q, ns and the six position σ/covariance terms from token i on; returns the next token's index.
  std::size_t parse_quality_and_covariance(const std::array<std::string_view, kMaxTokens>& tok, std::size_t i,
                                           long line, const PosHeader& h, PosEpoch* e) const {
    long long q, ns;
    if (!to_int(tok[i], &q)) bad_field(line, i, tok[i], "is not an integer");
    if (q < 1 || q > 6)
      bad_field(line, i, tok[i], "is outside 1-6 (1 fix, 2 float, 3 sbas, 4 dgps, 5 single, 6 ppp)");
    e->quality = static_cast<int>(q);
    ++i;
    if (!to_int(tok[i], &ns) || ns < 0 || ns > 1000) bad_field(line, i, tok[i], "is not a satellite count");
    e->ns = static_cast<int>(ns);
    ++i;
    const double s0 = sd(tok, i, line), s1 = sd(tok, i + 1, line), s2 = sd(tok, i + 2, line);
    const std::string sq = "signed square root of a covariance, m";
    const double c01 = cov_from_signed_sqrt(num_in(tok, i + 3, line, -kMaxSigmaM, kMaxSigmaM, sq));
    const double c12 = cov_from_signed_sqrt(num_in(tok, i + 4, line, -kMaxSigmaM, kMaxSigmaM, sq));
    const double c20 = cov_from_signed_sqrt(num_in(tok, i + 5, line, -kMaxSigmaM, kMaxSigmaM, sq));
    Eigen::Matrix3d& C = e->covariance;
    switch (h.position_format) {
      case PosPositionFormat::llh_deg:
      case PosPositionFormat::llh_dms:
        // sdn sde sdu sdne sdeu sdun → covariance in E, N, U order.
        C << s1 * s1, c01, c12,  //
            c01, s0 * s0, c20,   //
            c12, c20, s2 * s2;
        break;
      case PosPositionFormat::enu_baseline:
        // sde sdn sdu sden sdnu sdue.
        C << s0 * s0, c01, c20,  //
            c01, s1 * s1, c12,   //
            c20, c12, s2 * s2;
        break;
      case PosPositionFormat::ecef:
        // sdx sdy sdz sdxy sdyz sdzx.
        C << s0 * s0, c01, c20,  //
            c01, s1 * s1, c12,   //
            c20, c12, s2 * s2;
        break;
    }
    return i + 6;
  }

  // The 9 velocity columns from token i on.
  void parse_velocity(const std::array<std::string_view, kMaxTokens>& tok, std::size_t i, long line,
                      const PosHeader& h, PosEpoch* e) const {
    const std::string sq = "signed square root of a covariance, m";
    double v[3];
    for (int k = 0; k < 3; ++k)
      v[k] = num_in(tok, i + k, line, -kMaxVelocityMps, kMaxVelocityMps, "velocity, m/s");
    const double t0 = sd(tok, i + 3, line), t1 = sd(tok, i + 4, line), t2 = sd(tok, i + 5, line);
    const double d01 = cov_from_signed_sqrt(num_in(tok, i + 6, line, -kMaxSigmaM, kMaxSigmaM, sq));
    const double d12 = cov_from_signed_sqrt(num_in(tok, i + 7, line, -kMaxSigmaM, kMaxSigmaM, sq));
    const double d20 = cov_from_signed_sqrt(num_in(tok, i + 8, line, -kMaxSigmaM, kMaxSigmaM, sq));
    e->has_velocity = true;
    Eigen::Matrix3d& V = e->velocity_covariance;
    if (h.position_format == PosPositionFormat::ecef) {
      // vx vy vz sdvx sdvy sdvz sdvxy sdvyz sdvzx.
      e->velocity = Eigen::Vector3d(v[0], v[1], v[2]);
      V << t0 * t0, d01, d20,  //
          d01, t1 * t1, d12,   //
          d20, d12, t2 * t2;
    } else {
      // vn ve vu sdvn sdve sdvu sdvne sdveu sdvun → E, N, U.
      e->velocity = Eigen::Vector3d(v[1], v[0], v[2]);
      V << t1 * t1, d01, d12,  //
          d01, t0 * t0, d20,   //
          d12, d20, t2 * t2;
    }
  }

  PosEpoch parse_epoch(const std::array<std::string_view, kMaxTokens>& tok, std::size_t n, long line,
                       const PosHeader& h) const {
    check_field_count(n, line);
    PosEpoch e;
    e.line = line;
    e.utc = to_utc(parse_time_reading(tok, line, h.time_format), h.time_system);
    std::size_t i = parse_position(tok, line, h, &e);
    i = parse_quality_and_covariance(tok, i, line, h, &e);
    // RTKLIB prints small negative ages (-0.01 s) when the base epoch is ahead: sign is not checked.
    e.age_s = num_in(tok, i++, line, -kMaxAgeS, kMaxAgeS, "age of differential, s");
    e.ratio = num_in(tok, i++, line, 0, kMaxRatio, "ambiguity ratio");
    if (h.has_velocity) parse_velocity(tok, i, line, h, &e);
    return e;
  }

  std::string_view text_;
  const std::string& path_;
  Layout layout_;
  std::string time_field_ = "time";
};

}  // namespace

PosFile parse_rtklib_pos(std::string_view text, const std::string& path) {
  return PosParser(strip_utf8_bom(text), path).run();
}

PosFile read_rtklib_pos(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw_input_error(path, 0, "", "cannot open RTKLIB .pos file (missing or unreadable)");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  std::string text;
  if (size > 0) {
    text.resize(static_cast<std::size_t>(size));
    in.read(text.data(), size);
    if (!in) throw_input_error(path, 0, "", "read error");
  }
  return parse_rtklib_pos(text, path);
}

const char* rtklib_quality_name(int q) {
  switch (q) {
    case 1:
      return "fix";
    case 2:
      return "float";
    case 3:
      return "sbas";
    case 4:
      return "dgps";
    case 5:
      return "single";
    case 6:
      return "ppp";
    default:
      return "?";
  }
}

}  // namespace rangecal
