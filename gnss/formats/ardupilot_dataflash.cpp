#include "gnss/formats/ardupilot_dataflash.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "gnss/formats/autopilot_attitude_series.hpp"
#include "gnss/formats/binary_log_bytes.hpp"

namespace rangecal {
namespace {

constexpr unsigned char kHead0 = 0xA3, kHead1 = 0x95;
constexpr std::size_t kHeadBytes = 3;
constexpr std::uint8_t kFmtType = 128;
// FMT: head, Type, Length, Name[4], Format[16], Columns[64].
constexpr std::uint8_t kFmtLength = 89;
constexpr std::size_t kFmtName = 5, kFmtFormat = 9, kFmtColumns = 25;
constexpr std::int64_t kMsPerWeek = 604'800'000;
constexpr std::int64_t kMaxWeek = 6000;
// Beyond this a boot time in µs is garbage (127 years), and ns products would overflow.
constexpr std::int64_t kMaxPlausibleUs = 4'000'000'000'000'000;

enum class Kind { integer, unsigned_integer, real, text };
struct Char {
  char c;
  std::uint8_t size;
  Kind kind;
  double scale;
};
// LogStructure.h's table of format characters.
constexpr Char kChars[] = {
    {'b', 1, Kind::integer, 1},    {'B', 1, Kind::unsigned_integer, 1},
    {'h', 2, Kind::integer, 1},    {'H', 2, Kind::unsigned_integer, 1},
    {'i', 4, Kind::integer, 1},    {'I', 4, Kind::unsigned_integer, 1},
    {'f', 4, Kind::real, 1},       {'d', 8, Kind::real, 1},
    {'n', 4, Kind::text, 1},       {'N', 16, Kind::text, 1},
    {'Z', 64, Kind::text, 1},      {'a', 64, Kind::text, 1},
    {'c', 2, Kind::integer, 0.01}, {'C', 2, Kind::unsigned_integer, 0.01},
    {'e', 4, Kind::integer, 0.01}, {'E', 4, Kind::unsigned_integer, 0.01},
    {'L', 4, Kind::integer, 1e-7}, {'M', 1, Kind::unsigned_integer, 1},
    {'q', 8, Kind::integer, 1},    {'Q', 8, Kind::unsigned_integer, 1},
};

const Char* find_char(char c) {
  for (const Char& k : kChars)
    if (k.c == c) return &k;
  return nullptr;
}

std::string dataflash_at_byte(std::size_t offset) {
  return "at byte " + std::to_string(offset) + ": ";
}

std::string hex2(unsigned char a, unsigned char b) {
  static const char* hex = "0123456789ABCDEF";
  return std::string{hex[a >> 4], hex[a & 15], ' ', hex[b >> 4], hex[b & 15]};
}

DataflashFormat builtin_fmt() {
  DataflashFormat f;
  f.type = kFmtType;
  f.length = kFmtLength;
  f.name = "FMT";
  f.format = "BBnNZ";
  f.columns = {"Type", "Length", "Name", "Format", "Columns"};
  f.offsets = {3, 4, kFmtName, kFmtFormat, kFmtColumns};
  return f;
}

bool plain_name(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u > 0x20 && u < 0x7f && c != ',';
  });
}

class Walker {
 public:
  Walker(std::string_view bytes, const std::string& path) : b_(bytes) {
    s_.path = path;
    s_.file_bytes = bytes.size();
    index_[kFmtType] = 0;
    s_.formats.push_back(builtin_fmt());
  }

  DataflashSummary run(const DataflashVisitor& visit) {
    std::size_t pos = 0;
    while (pos < b_.size()) {
      const std::size_t left = b_.size() - pos;
      if (left < kHeadBytes) {
        s_.truncated_bytes = left;
        break;
      }
      const auto h0 = static_cast<unsigned char>(b_[pos]), h1 = static_cast<unsigned char>(b_[pos + 1]);
      if (h0 != kHead0 || h1 != kHead1)
        fail("message head", pos, "expected a message head A3 95, found " + hex2(h0, h1));
      const auto type = static_cast<std::uint8_t>(b_[pos + 2]);
      if (index_[type] < 0)
        fail("type " + std::to_string(type), pos,
             "message type " + std::to_string(type) + " has no FMT message defining it before this point");
      DataflashFormat& f = s_.formats[static_cast<std::size_t>(index_[type])];
      if (f.length > left) {
        s_.truncated_bytes = left;
        break;
      }
      const std::size_t length = f.length;
      const std::string_view m = b_.substr(pos, length);
      ++s_.messages;
      ++f.messages;
      if (type == kFmtType) {
        define(m, pos);  // may grow s_.formats: `f` is not used after this
      } else {
        visit(f, m);
      }
      pos += length;
    }
    return std::move(s_);
  }

 private:
  [[noreturn]] void fail(const std::string& field, std::size_t offset, const std::string& why) const {
    throw_input_error(s_.path, 0, field, dataflash_at_byte(offset) + why);
  }

  void define(std::string_view m, std::size_t at) {
    DataflashFormat f;
    f.type = static_cast<std::uint8_t>(m[3]);
    f.length = static_cast<std::uint8_t>(m[4]);
    f.name = std::string(until_nul(m.substr(kFmtName, 4)));
    f.format = std::string(until_nul(m.substr(kFmtFormat, 16)));
    f.byte_offset = at;
    const std::string_view columns = until_nul(m.substr(kFmtColumns, 64));
    const std::string field = "FMT " + quote_log_text(f.name);
    const std::string what = "type " + std::to_string(f.type) + " (" + quote_log_text(f.name) + ")";
    if (!plain_name(f.name)) fail(field, at, what + ": the name is empty or not printable ASCII");
    std::size_t size = kHeadBytes;
    for (char c : f.format) {
      const Char* k = find_char(c);
      if (!k)
        fail(field, at,
             what + ": format character '" + quote_log_text(std::string_view(&c, 1)) +
                 "' is not a DataFlash type");
      f.offsets.push_back(static_cast<std::uint16_t>(size));
      size += k->size;
    }
    if (f.length != size)
      fail(field, at,
           what + ": Length is " + std::to_string(f.length) + " bytes but its format '" +
               quote_log_text(f.format) + "' takes " + std::to_string(size) + " (3-byte head included)");
    std::size_t start = 0;
    while (start <= columns.size() && !columns.empty()) {
      const std::size_t comma = std::min(columns.find(',', start), columns.size());
      f.columns.emplace_back(columns.substr(start, comma - start));
      if (!plain_name(f.columns.back()))
        fail(field, at,
             what + ": column " + std::to_string(f.columns.size()) + " has an empty or unprintable name");
      start = comma + 1;
    }
    if (f.columns.size() != f.format.size())
      fail(field, at,
           what + ": " + std::to_string(f.columns.size()) + " column names for " +
               std::to_string(f.format.size()) + " format characters");
    if (const int i = index_[f.type]; i >= 0) {
      const DataflashFormat& g = s_.formats[static_cast<std::size_t>(i)];
      if (g.length != f.length || g.name != f.name || g.format != f.format || g.columns != f.columns)
        fail(field, at,
             what + " is defined again differently (first definition at byte " +
                 std::to_string(g.byte_offset) + ")");
      return;
    }
    for (const DataflashFormat& g : s_.formats)
      if (g.name == f.name)
        fail(field, at, what + ": the name is already used by type " + std::to_string(g.type));
    index_[f.type] = static_cast<int>(s_.formats.size());
    s_.formats.push_back(std::move(f));
  }

  std::string_view b_;
  DataflashSummary s_;
  std::array<int, 256> index_ = [] {
    std::array<int, 256> a{};
    a.fill(-1);
    return a;
  }();
};

// Columns the attitude needs, checked once per type.
struct Columns {
  std::vector<std::size_t> index;
  std::optional<std::size_t> instance;
};

Columns need_columns(const DataflashFormat& f, const std::vector<std::string>& names, const std::string& path,
                     bool integers) {
  Columns c;
  for (const std::string& n : names) {
    const auto i = dataflash_column(f, n);
    const std::string field = "FMT " + f.name + "." + n;
    if (!i)
      throw_input_error(path, 0, field,
                        dataflash_at_byte(f.byte_offset) + "type " + f.name + " has no column '" + n +
                            "', needed to put the attitude on UTC");
    const Kind k = find_char(f.format[*i])->kind;
    if (k == Kind::text || (integers && k == Kind::real) || (integers && find_char(f.format[*i])->scale != 1))
      throw_input_error(path, 0, field,
                        dataflash_at_byte(f.byte_offset) + "column is of format character '" +
                            quote_log_text(std::string_view(&f.format[*i], 1)) + "', expected " +
                            (integers ? "an integer" : "a number"));
    c.index.push_back(*i);
  }
  return c;
}

}  // namespace

bool is_dataflash(std::string_view head) {
  return head.size() >= kHeadBytes && static_cast<unsigned char>(head[0]) == kHead0 &&
         static_cast<unsigned char>(head[1]) == kHead1 && static_cast<std::uint8_t>(head[2]) == kFmtType;
}

DataflashSummary walk_dataflash(std::string_view bytes, const std::string& path,
                                const DataflashVisitor& visit) {
  return Walker(bytes, path).run(visit);
}

std::optional<std::size_t> dataflash_column(const DataflashFormat& f, std::string_view name) {
  for (std::size_t i = 0; i < f.columns.size(); ++i)
    if (f.columns[i] == name) return i;
  return std::nullopt;
}

std::optional<std::int64_t> dataflash_integer(const DataflashFormat& f, std::size_t column,
                                              std::string_view m) {
  if (column >= f.format.size()) return std::nullopt;
  const Char* k = find_char(f.format[column]);
  if (!k || (k->kind != Kind::integer && k->kind != Kind::unsigned_integer)) return std::nullopt;
  if (f.offsets[column] + std::size_t{k->size} > m.size()) return std::nullopt;
  const char* p = m.data() + f.offsets[column];
  if (k->kind == Kind::integer) {
    switch (k->size) {
      case 1:
        return load_i8(p);
      case 2:
        return load_i16(p);
      case 4:
        return load_i32(p);
      default:
        return load_i64(p);
    }
  }
  switch (k->size) {
    case 1:
      return load_u8(p);
    case 2:
      return load_u16(p);
    case 4:
      return load_u32(p);
    default: {
      const std::uint64_t v = load_u64(p);
      if (v > static_cast<std::uint64_t>(INT64_MAX)) return std::nullopt;
      return static_cast<std::int64_t>(v);
    }
  }
}

std::optional<double> dataflash_number(const DataflashFormat& f, std::size_t column, std::string_view m) {
  if (column >= f.format.size()) return std::nullopt;
  const Char* k = find_char(f.format[column]);
  if (!k || k->kind == Kind::text || f.offsets[column] + std::size_t{k->size} > m.size()) return std::nullopt;
  const char* p = m.data() + f.offsets[column];
  if (k->kind == Kind::real) return k->size == 4 ? static_cast<double>(load_f32(p)) : load_f64(p);
  if (k->kind == Kind::unsigned_integer && k->size == 8) return static_cast<double>(load_u64(p)) * k->scale;
  return static_cast<double>(*dataflash_integer(f, column, m)) * k->scale;
}

AttitudeSeries dataflash_attitude(std::string_view bytes, const std::string& path,
                                  AutopilotAttitudeReport* report, std::optional<double> gnss_lag_ms) {
  AutopilotAttitudeReport rep;
  rep.format = "ardupilot_dataflash";
  rep.file_bytes = bytes.size();
  rep.attitude_message = "ATT";
  rep.attitude_time_field = "TimeUS";
  rep.gps_message = "GPS";
  std::vector<BootAttitudeSample> raw;
  std::vector<BootUtcPair> pairs;
  std::optional<Columns> att, gps;
  const DataflashSummary sum = walk_dataflash(bytes, path, [&](const DataflashFormat& f, std::string_view m) {
    if (f.name == "ATT") {
      if (!att) {
        att = need_columns(f, {"TimeUS"}, path, true);
        const Columns rpy = need_columns(f, {"Roll", "Pitch", "Yaw"}, path, false);
        att->index.insert(att->index.end(), rpy.index.begin(), rpy.index.end());
      }
      ++rep.attitude_messages;
      const auto t = dataflash_integer(f, att->index[0], m);
      Attitude a;
      a.roll_deg = *dataflash_number(f, att->index[1], m);
      a.pitch_deg = *dataflash_number(f, att->index[2], m);
      a.yaw_deg = *dataflash_number(f, att->index[3], m);
      // ArduPilot logs roll in [-180, 180], pitch in [-90, 90], yaw in [0, 360]; anything else
      // (NaN from an uninitialised estimator, garbage) is not an attitude.
      if (!t || *t <= 0 || *t > kMaxPlausibleUs || !(std::abs(a.roll_deg) <= 180) ||
          !(std::abs(a.pitch_deg) <= 90) || !(std::abs(a.yaw_deg) <= 360)) {
        ++rep.attitude_invalid;
        return;
      }
      a.yaw_deg = wrap_deg_180(a.yaw_deg);
      raw.push_back({*t, a});
    } else if (f.name == "GPS") {
      if (!gps) {
        gps = need_columns(f, {"TimeUS", "Status", "GWk", "GMS"}, path, true);
        if (const auto i = dataflash_column(f, "I"))
          gps->instance = need_columns(f, {"I"}, path, true).index[0];
      }
      if (gps->instance && dataflash_integer(f, *gps->instance, m).value_or(-1) != 0) return;
      ++rep.gps_messages;
      const auto t = dataflash_integer(f, gps->index[0], m), status = dataflash_integer(f, gps->index[1], m),
                 week = dataflash_integer(f, gps->index[2], m), ms = dataflash_integer(f, gps->index[3], m);
      // GPS_OK_FIX_3D = 3 in AP_GPS's status enum; higher values are better fixes. Week 0 is a
      // receiver without time; week 6000 (year 2095) bounds a garbage week before it overflows
      // the ns arithmetic.
      if (!t || !status || !week || !ms || *status < 3 || *week <= 0 || *week >= kMaxWeek || *ms < 0 ||
          *ms >= kMsPerWeek || *t > kMaxPlausibleUs) {
        ++rep.gps_skipped;
        return;
      }
      pairs.push_back({*t, gps_to_utc(gps_from_week_tow(static_cast<int>(*week), *ms * 1'000'000))});
    }
  });
  rep.truncated_bytes = sum.truncated_bytes;
  const auto defined = [&](const char* name) {
    return std::any_of(sum.formats.begin(), sum.formats.end(),
                       [&](const DataflashFormat& f) { return f.name == name; });
  };
  if (!defined("ATT"))
    throw_input_error(path, 0, "FMT ATT", "the log defines no ATT message type: it holds no attitude");
  if (!defined("GPS"))
    throw_input_error(path, 0, "FMT GPS",
                      "the log defines no GPS message type: its boot time cannot be mapped to UTC");
  rep.gnss_lag_ms = gnss_lag_ms.value_or(kDataflashDefaultGnssLagMs);
  rep.gnss_lag_given = gnss_lag_ms.has_value();
  rep.fit = fit_boot_time(std::move(pairs), path, "GPS.GMS", boot_time_options_for_lag(rep.gnss_lag_ms));

  return autopilot_attitude_series(raw, path, {"ATT", "ATT messages", "out of range or without a time"},
                                   std::move(rep), report);
}

AttitudeSeries read_dataflash_attitude(const std::string& path, AutopilotAttitudeReport* report,
                                       std::optional<double> gnss_lag_ms) {
  const std::string bytes = read_file_text(path);
  return dataflash_attitude(bytes, path, report, gnss_lag_ms);
}

}  // namespace rangecal
