#include "gnss/formats/px4_ulog.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/formats/autopilot_attitude_series.hpp"
#include "gnss/formats/binary_log_bytes.hpp"

namespace rangecal {
namespace {

// "Header Section": 7 magic bytes, version, uint64 timestamp.
constexpr char kMagic[7] = {'U', 'L', 'o', 'g', 0x01, 0x12, 0x35};
constexpr std::size_t kHeaderBytes = 16;
// "Definitions Section": every message starts with uint16 msg_size (body bytes) and uint8 msg_type.
constexpr std::size_t kMessageHeaderBytes = 3;
// A D message body is uint16 msg_id + data, at most 65535 bytes: no format can be larger.
constexpr std::uint32_t kMaxDataBytes = 65535 - 2;
// PX4 nests formats two or three deep; the bound keeps the recursion's stack small on any input.
constexpr int kMaxNesting = 32;
// "Flag Bits Message": the only incompatible flag defined, bit 0 of incompat_flags[0].
constexpr std::uint8_t kDataAppendedBit = 1;
// Beyond this, a boot or UTC time in µs is garbage (127 years), and ns products would overflow.
constexpr std::uint64_t kMaxPlausibleUlogUs = 4'000'000'000'000'000;

struct TypeInfo {
  UlogType type;
  const char* name;
  std::size_t size;
};
// "Data Types".
constexpr TypeInfo kTypes[] = {
    {UlogType::int8, "int8_t", 1},     {UlogType::uint8, "uint8_t", 1},   {UlogType::int16, "int16_t", 2},
    {UlogType::uint16, "uint16_t", 2}, {UlogType::int32, "int32_t", 4},   {UlogType::uint32, "uint32_t", 4},
    {UlogType::int64, "int64_t", 8},   {UlogType::uint64, "uint64_t", 8}, {UlogType::float32, "float", 4},
    {UlogType::float64, "double", 8},  {UlogType::boolean, "bool", 1},    {UlogType::character, "char", 1},
};

const TypeInfo* primitive(std::string_view name) {
  for (const TypeInfo& t : kTypes)
    if (name == t.name) return &t;
  return nullptr;
}

const char* type_name(UlogType t) {
  for (const TypeInfo& i : kTypes)
    if (i.type == t) return i.name;
  return "nested format";
}

std::string ulog_at_byte(std::size_t offset) {
  return "at byte " + std::to_string(offset) + ": ";
}

// "type name" or "type[n] name", as in format fields and info keys.
struct TypedName {
  std::string type;
  std::uint32_t count = 1;
  bool is_array = false;
  std::string name;
};

bool name_char_ok(char c) {
  const auto u = static_cast<unsigned char>(c);
  return u > 0x20 && u < 0x7f && c != ';' && c != ':' && c != '[' && c != ']';
}

std::optional<TypedName> parse_typed_name(std::string_view s, std::string* why) {
  const std::size_t sp = s.find(' ');
  if (sp == std::string_view::npos || sp == 0 || sp + 1 >= s.size()) {
    *why = "'" + quote_log_text(s) + "' is not of the form 'type name'";
    return std::nullopt;
  }
  TypedName r;
  std::string_view type = s.substr(0, sp), name = s.substr(sp + 1);
  if (!std::all_of(name.begin(), name.end(), name_char_ok)) {
    *why = "field name '" + quote_log_text(name) + "' has characters outside printable ASCII or ' ;:[]'";
    return std::nullopt;
  }
  if (const std::size_t lb = type.find('['); lb != std::string_view::npos) {
    if (type.back() != ']' || lb == 0) {
      *why = "type '" + quote_log_text(type) + "' is not of the form 'type[n]'";
      return std::nullopt;
    }
    const std::string_view digits = type.substr(lb + 1, type.size() - lb - 2);
    std::uint64_t n = 0;
    if (digits.empty() || digits.size() > 5 ||
        !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      *why = "array length in '" + quote_log_text(type) + "' is not a number of at most 5 digits";
      return std::nullopt;
    }
    for (char c : digits) n = n * 10 + static_cast<std::uint64_t>(c - '0');
    if (n > kMaxDataBytes) {
      *why = "array length " + std::to_string(n) + " in '" + quote_log_text(type) + "' exceeds " +
             std::to_string(kMaxDataBytes);
      return std::nullopt;
    }
    r.count = static_cast<std::uint32_t>(n);
    r.is_array = true;
    type = type.substr(0, lb);
  }
  if (!std::all_of(type.begin(), type.end(), name_char_ok)) {
    *why = "type '" + quote_log_text(type) + "' has characters outside printable ASCII or ' ;:[]'";
    return std::nullopt;
  }
  r.type = std::string(type);
  r.name = std::string(name);
  return r;
}

std::string number_text(UlogType t, const char* p) {
  switch (t) {
    case UlogType::int8:
      return std::to_string(load_i8(p));
    case UlogType::uint8:
      return std::to_string(load_u8(p));
    case UlogType::int16:
      return std::to_string(load_i16(p));
    case UlogType::uint16:
      return std::to_string(load_u16(p));
    case UlogType::int32:
      return std::to_string(load_i32(p));
    case UlogType::uint32:
      return std::to_string(load_u32(p));
    case UlogType::int64:
      return std::to_string(load_i64(p));
    case UlogType::uint64:
      return std::to_string(load_u64(p));
    case UlogType::float32:
      return fmt::format("{:.9g}", static_cast<double>(load_f32(p)));
    case UlogType::float64:
      return fmt::format("{:.17g}", load_f64(p));
    case UlogType::boolean:
      return load_u8(p) ? "true" : "false";
    case UlogType::character:
      return quote_log_text(std::string_view(p, 1));
    case UlogType::nested:
      break;
  }
  return "";
}

// Value bytes of an I/M/P/Q message as text (see UlogInfo).
std::string value_text(const TypeInfo& t, const TypedName& k, std::string_view v) {
  if (t.type == UlogType::character) return quote_log_text(until_nul(v), 4096);
  if (!k.is_array) return number_text(t.type, v.data());
  std::string r = "[";
  for (std::uint32_t i = 0; i < k.count; ++i)
    r += (i ? ", " : "") + number_text(t.type, v.data() + i * t.size);
  return r + "]";
}

struct RawFormat {
  std::string name;
  std::string text;  // everything after the ':' (for duplicate checks)
  std::vector<TypedName> fields;
  std::size_t byte_offset = 0;
};

class UlogParser {
 public:
  UlogParser(std::string bytes, const std::string& path) {
    log_.bytes = std::move(bytes);
    log_.summary.path = path;
    log_.summary.file_bytes = log_.bytes.size();
  }

  UlogLog run() {
    read_header();
    std::size_t pos = kHeaderBytes;
    const std::size_t n = log_.bytes.size();
    std::size_t segment = 0;  // index into appended_ of the current segment's end (appended_.size(): EOF)
    std::size_t index = 0;
    while (pos < n) {
      const std::size_t end = segment < appended_.size() ? appended_[segment] : n;
      if (pos >= end) {  // reached an appended offset exactly: continue there
        pos = end;
        ++segment;
        continue;
      }
      const std::size_t left = end - pos;
      std::size_t body = 0;
      if (left >= kMessageHeaderBytes) body = load_u16(ptr(pos));
      if (left < kMessageHeaderBytes || kMessageHeaderBytes + body > left) {
        // The log stops inside this message (power cut, or the logger stopped before the data
        // appended at `end`): count the bytes and go on at the next segment, if any.
        log_.summary.truncated_bytes += left;
        pos = end;
        ++segment;
        continue;
      }
      message(static_cast<char>(log_.bytes[pos + 2]), pos, body, index++);
      pos += kMessageHeaderBytes + body;
    }
    resolve_all();
    finish_summary();
    return std::move(log_);
  }

 private:
  const std::string& path() const { return log_.summary.path; }
  const char* ptr(std::size_t offset) const { return log_.bytes.data() + offset; }
  [[noreturn]] void fail(const std::string& field, std::size_t offset, const std::string& why) const {
    throw_input_error(path(), 0, field, ulog_at_byte(offset) + why);
  }

  void read_header() {
    const std::string& b = log_.bytes;
    if (b.size() < kHeaderBytes)
      fail("header", 0,
           "the file is " + std::to_string(b.size()) + " bytes, shorter than the 16-byte ULog header");
    if (!is_ulog(b))
      fail("header", 0, "not a ULog file: the first 7 bytes are not the magic 'ULog' 01 12 35");
    // "Requirements for Parsers": future versions are parsed as well (the summary reports it).
    log_.summary.version = static_cast<unsigned char>(b[7]);
    log_.summary.header_timestamp_us = load_u64(ptr(8));
  }

  void message(char type, std::size_t at, std::size_t size, std::size_t index) {
    const std::size_t body = at + kMessageHeaderBytes;
    switch (type) {
      case 'B':
        flag_bits(at, body, size, index);
        break;
      case 'F':
        format(at, std::string_view(ptr(body), size));
        break;
      case 'I':
        info(at, body, size);
        break;
      case 'M':
        multi_info(at, body, size);
        break;
      case 'P':
        key_value("P", at, body, size);
        ++log_.summary.parameters;
        break;
      case 'Q':
        need("Q", at, size, 1);
        key_value("Q", at, body + 1, size - 1);
        ++log_.summary.default_parameters;
        break;
      case 'A':
        add_subscription(at, body, size);
        break;
      case 'R':
        remove_subscription(at, body, size);
        break;
      case 'D':
        data(at, body, size);
        break;
      case 'L':  // uint8 log_level, uint64 timestamp, char message[]
        need("L", at, size, 9);
        ++log_.summary.logged_strings;
        break;
      case 'C':  // uint8 log_level, uint16 tag, uint64 timestamp, char message[]
        need("C", at, size, 11);
        ++log_.summary.logged_strings;
        break;
      case 'S':
        ++log_.summary.syncs;
        break;
      case 'O':  // uint16 duration in ms
        need("O", at, size, 2);
        ++log_.summary.dropouts;
        log_.summary.dropout_ms += load_u16(ptr(body));
        break;
      default:
        ++log_.summary.unknown_messages;
        break;
    }
  }

  void need(const std::string& field, std::size_t at, std::size_t size, std::size_t min) const {
    if (size < min)
      fail(field, at,
           "message body is " + std::to_string(size) + " bytes, fewer than the " + std::to_string(min) +
               " its fixed fields take");
  }

  // "Flag Bits Message": uint8 compat_flags[8], uint8 incompat_flags[8], uint64 appended_offsets[3].
  void flag_bits(std::size_t at, std::size_t body, std::size_t size, std::size_t index) {
    if (index != 0) fail("B", at, "the flag bits message must be the first message after the header");
    need("B", at, size, 40);
    const char* incompat = ptr(body + 8);
    for (int i = 0; i < 8; ++i) {
      const std::uint8_t known = i == 0 ? kDataAppendedBit : 0;
      const std::uint8_t v = load_u8(incompat + i);
      if (v & ~known)
        fail("B incompat_flags", body + 8 + static_cast<std::size_t>(i),
             "incompatible flag bits " + std::to_string(v) + " in byte " + std::to_string(i) +
                 " are not known to this reader: the log needs a newer ULog parser");
    }
    if (!(load_u8(incompat) & kDataAppendedBit)) return;
    log_.summary.data_appended = true;
    std::size_t previous = body + size;
    for (int i = 0; i < 3; ++i) {
      const std::uint64_t off = load_u64(ptr(body + 16 + 8 * static_cast<std::size_t>(i)));
      if (off == 0) continue;
      if (off < previous || off > log_.bytes.size())
        fail("B appended_offsets", body + 16 + 8 * static_cast<std::size_t>(i),
             "appended offset " + std::to_string(off) + " is outside [" + std::to_string(previous) + ", " +
                 std::to_string(log_.bytes.size()) +
                 "] (after the flag bits message, increasing, in the file)");
      appended_.push_back(static_cast<std::size_t>(off));
      previous = static_cast<std::size_t>(off);
    }
  }

  // "Format Message": "name:type field;type field;…".
  void format(std::size_t at, std::string_view text) {
    const std::size_t colon = text.find(':');
    if (colon == std::string_view::npos || colon == 0)
      fail("F", at, "format '" + quote_log_text(text) + "' is not of the form 'name:type field;…'");
    RawFormat f;
    f.name = std::string(text.substr(0, colon));
    f.text = std::string(text.substr(colon + 1));
    f.byte_offset = at;
    if (!std::all_of(f.name.begin(), f.name.end(), name_char_ok))
      fail("F", at,
           "format name '" + quote_log_text(f.name) + "' has characters outside printable ASCII or ' ;:[]'");
    const std::string fname = "F " + quote_log_text(f.name);
    std::string_view rest = text.substr(colon + 1);
    while (!rest.empty()) {
      const std::size_t semi = rest.find(';');
      const std::string_view piece = rest.substr(0, semi);
      rest = semi == std::string_view::npos ? std::string_view() : rest.substr(semi + 1);
      if (piece.empty()) continue;
      std::string why;
      const auto tn = parse_typed_name(piece, &why);
      if (!tn) fail(fname, at, why);
      for (const TypedName& g : f.fields)
        if (g.name == tn->name) fail(fname + "." + quote_log_text(g.name), at, "field defined twice");
      f.fields.push_back(*tn);
    }
    if (const auto it = format_index_.find(f.name); it != format_index_.end()) {
      if (raw_[it->second].text != f.text)
        fail(fname, at,
             "format defined a second time, differently (first at byte " +
                 std::to_string(raw_[it->second].byte_offset) + ")");
      return;
    }
    format_index_.emplace(f.name, raw_.size());
    raw_.push_back(std::move(f));
    state_.push_back(0);
    log_.formats.emplace_back();
  }

  // Resolves raw format i into log_.formats[i]: types, offsets, sizes.
  void resolve(std::size_t i, int depth) {
    if (state_[i] == 2) return;
    const RawFormat& r = raw_[i];
    const std::string fname = "F " + quote_log_text(r.name);
    if (state_[i] == 1) fail(fname, r.byte_offset, "format contains itself (through its nested fields)");
    if (depth > kMaxNesting)
      fail(fname, r.byte_offset, "formats are nested more than " + std::to_string(kMaxNesting) + " deep");
    state_[i] = 1;
    UlogFormat f;
    f.name = r.name;
    f.byte_offset = r.byte_offset;
    std::uint64_t offset = 0;
    for (const TypedName& tn : r.fields) {
      UlogField field;
      field.name = tn.name;
      field.type_name = tn.type;
      field.count = tn.count;
      field.is_array = tn.is_array;
      std::uint64_t element = 0;
      if (const TypeInfo* t = primitive(tn.type)) {
        field.type = t->type;
        element = t->size;
      } else {
        const auto it = format_index_.find(tn.type);
        if (it == format_index_.end())
          fail(fname + "." + quote_log_text(tn.name), r.byte_offset,
               "type '" + quote_log_text(tn.type) +
                   "' is neither a ULog base type nor a format defined in the log");
        resolve(it->second, depth + 1);
        field.type = UlogType::nested;
        field.nested = it->second;
        element = log_.formats[it->second].size;
      }
      const std::uint64_t size = element * tn.count;  // ≤ 65533², no overflow
      field.offset = static_cast<std::uint32_t>(offset);
      offset += size;
      if (offset > kMaxDataBytes)
        fail(fname + "." + quote_log_text(tn.name), r.byte_offset,
             "the format reaches " + std::to_string(offset) +
                 " bytes here, more than a D message can carry (" + std::to_string(kMaxDataBytes) + ")");
      field.size = static_cast<std::uint32_t>(size);
      f.fields.push_back(std::move(field));
    }
    f.size = static_cast<std::uint32_t>(offset);
    // "Format Message": trailing padding of a top-level message is not logged.
    f.logged_size = f.size;
    for (auto it = f.fields.rbegin(); it != f.fields.rend() && it->name.rfind("_padding", 0) == 0; ++it)
      f.logged_size -= it->size;
    log_.formats[i] = std::move(f);
    state_[i] = 2;
  }

  void resolve_all() {
    for (std::size_t i = 0; i < raw_.size(); ++i) resolve(i, 0);
  }

  // I / P / Q body: uint8 key_len, char key[key_len] ("type name"), value bytes.
  std::pair<TypedName, std::string> key_value(const std::string& kind, std::size_t at, std::size_t body,
                                              std::size_t size) {
    need(kind, at, size, 1);
    const std::size_t key_len = load_u8(ptr(body));
    if (1 + key_len > size)
      fail(kind, at,
           "key length " + std::to_string(key_len) + " runs past the message body of " +
               std::to_string(size) + " bytes");
    const std::string_view key(ptr(body + 1), key_len);
    std::string why;
    const auto tn = parse_typed_name(key, &why);
    if (!tn) fail(kind, at, why);
    const std::string field = kind + " " + quote_log_text(tn->name);
    const TypeInfo* t = primitive(tn->type);
    if (!t) fail(field, at, "type '" + quote_log_text(tn->type) + "' is not a ULog base type");
    const std::string_view value(ptr(body + 1 + key_len), size - 1 - key_len);
    if (value.size() != t->size * tn->count)
      fail(field, at,
           "value is " + std::to_string(value.size()) + " bytes, its type " +
               quote_log_text(key.substr(0, key.find(' '))) + " takes " +
               std::to_string(t->size * tn->count));
    return {*tn, value_text(*t, *tn, value)};
  }

  void info(std::size_t at, std::size_t body, std::size_t size) {
    auto [tn, value] = key_value("I", at, body, size);
    UlogInfo i;
    i.key = tn.name;
    i.type = tn.type + (tn.is_array ? "[" + std::to_string(tn.count) + "]" : "");
    i.value = std::move(value);
    log_.summary.info.push_back(std::move(i));
  }

  // "Multi Information Message": uint8 is_continued, then as I.
  void multi_info(std::size_t at, std::size_t body, std::size_t size) {
    need("M", at, size, 2);
    const bool continued = load_u8(ptr(body)) != 0;
    auto [tn, value] = key_value("M", at, body + 1, size - 1);
    std::size_t& n = log_.summary.multi_info[tn.name];
    if (!continued || n == 0) ++n;
  }

  // "Subscription Message": uint8 multi_id, uint16 msg_id, char message_name[].
  void add_subscription(std::size_t at, std::size_t body, std::size_t size) {
    need("A", at, size, 4);
    if (!definitions_done_) {
      definitions_done_ = true;
      resolve_all();
    }
    UlogSubscription s;
    s.multi_id = load_u8(ptr(body));
    s.msg_id = load_u16(ptr(body + 1));
    s.topic = std::string(ptr(body + 3), size - 3);
    s.byte_offset = at;
    const std::string field = "A " + quote_log_text(s.topic);
    const auto it = format_index_.find(s.topic);
    if (it == format_index_.end())
      fail(field, at,
           "subscription (msg_id " + std::to_string(s.msg_id) + ") to a topic with no format in the log");
    resolve(it->second, 0);
    s.format = it->second;
    if (active_[s.msg_id] >= 0)
      fail(field, at,
           "msg_id " + std::to_string(s.msg_id) + " is already subscribed to '" +
               quote_log_text(log_.subscriptions[static_cast<std::size_t>(active_[s.msg_id])].topic) +
               "' (no R message removed it)");
    active_[s.msg_id] = static_cast<std::int32_t>(log_.subscriptions.size());
    const auto ts = find_ulog_field(log_, s.format, "timestamp");
    timestamp_offset_.push_back(ts && ts->type == UlogType::uint64 && ts->count == 1 &&
                                        ts->offset + 8 <= log_.formats[s.format].logged_size
                                    ? static_cast<std::int64_t>(ts->offset)
                                    : -1);
    log_.subscriptions.push_back(std::move(s));
  }

  void remove_subscription(std::size_t at, std::size_t body, std::size_t size) {
    need("R", at, size, 2);
    const std::uint16_t id = load_u16(ptr(body));
    if (active_[id] < 0) fail("R", at, "msg_id " + std::to_string(id) + " is not subscribed");
    active_[id] = -1;
  }

  // "Logged Data Message": uint16 msg_id, data.
  void data(std::size_t at, std::size_t body, std::size_t size) {
    need("D", at, size, 2);
    const std::uint16_t id = load_u16(ptr(body));
    if (active_[id] < 0)
      fail("D", at, "msg_id " + std::to_string(id) + " has no subscription (no A message before it)");
    const auto si = static_cast<std::size_t>(active_[id]);
    UlogSubscription& s = log_.subscriptions[si];
    const UlogFormat& f = log_.formats[s.format];
    const std::size_t n = size - 2;
    if (n < f.logged_size || n > f.size)
      fail("D " + quote_log_text(s.topic), at,
           "message carries " + std::to_string(n) + " data bytes, its format takes " +
               (f.logged_size == f.size ? std::to_string(f.size)
                                        : std::to_string(f.logged_size) + " to " + std::to_string(f.size)));
    ++s.messages;
    log_.data.push_back({si, body + 2, n});
    if (const std::int64_t o = timestamp_offset_[si]; o >= 0) {
      const std::uint64_t t = load_u64(ptr(body + 2 + static_cast<std::size_t>(o)));
      if (t == 0) return;  // a topic published before its first update carries no time
      UlogSummary& m = log_.summary;
      if (!m.first_timestamp_us || t < *m.first_timestamp_us) m.first_timestamp_us = t;
      if (!m.last_timestamp_us || t > *m.last_timestamp_us) m.last_timestamp_us = t;
    }
  }

  void finish_summary() {
    for (const UlogSubscription& s : log_.subscriptions) {
      auto it = std::find_if(
          log_.summary.topics.begin(), log_.summary.topics.end(),
          [&](const UlogTopicCount& t) { return t.topic == s.topic && t.multi_id == s.multi_id; });
      if (it == log_.summary.topics.end()) {
        log_.summary.topics.push_back({s.topic, s.multi_id, 0});
        it = log_.summary.topics.end() - 1;
      }
      it->messages += s.messages;
    }
    std::sort(log_.summary.topics.begin(), log_.summary.topics.end(),
              [](const UlogTopicCount& a, const UlogTopicCount& b) {
                return a.topic != b.topic ? a.topic < b.topic : a.multi_id < b.multi_id;
              });
  }

  UlogLog log_;
  std::vector<RawFormat> raw_;
  std::map<std::string, std::size_t> format_index_;
  std::vector<int> state_;  // per format: 0 unresolved, 1 resolving, 2 resolved
  bool definitions_done_ = false;
  std::vector<std::size_t> appended_;
  std::vector<std::int32_t> active_ = std::vector<std::int32_t>(65536, -1);  // msg_id → subscription
  std::vector<std::int64_t> timestamp_offset_;  // per subscription: offset of uint64 timestamp, or −1
};

// ---- attitude -------------------------------------------------------------------------------

// Subscriptions of `topic` with its lowest multi_id (several when it was removed and re-added).
std::vector<std::size_t> subscriptions_of(const UlogLog& log, const std::string& topic) {
  int lowest = 256;
  for (const UlogSubscription& s : log.subscriptions)
    if (s.topic == topic) lowest = std::min(lowest, static_cast<int>(s.multi_id));
  std::vector<std::size_t> r;
  for (std::size_t i = 0; i < log.subscriptions.size(); ++i)
    if (log.subscriptions[i].topic == topic && log.subscriptions[i].multi_id == lowest) r.push_back(i);
  return r;
}

std::size_t message_count(const UlogLog& log, const std::vector<std::size_t>& subs) {
  std::size_t n = 0;
  for (std::size_t i : subs) n += log.subscriptions[i].messages;
  return n;
}

// A field the extraction needs: present, of `type`, `count` elements, inside the logged bytes.
std::optional<UlogFieldRef> typed_field(const UlogLog& log, std::size_t format, const std::string& name,
                                        UlogType type, std::uint32_t count, bool required) {
  const UlogFormat& f = log.formats[format];
  const std::string field = "F " + quote_log_text(f.name) + "." + name;
  const auto r = find_ulog_field(log, format, name);
  if (!r) {
    if (!required) return std::nullopt;
    throw_input_error(log.summary.path, 0, field,
                      ulog_at_byte(f.byte_offset) + "the format has no field '" + name +
                          "', needed to put the attitude on UTC");
  }
  if (r->type != type || r->count != count)
    throw_input_error(log.summary.path, 0, field,
                      ulog_at_byte(f.byte_offset) + "field is " + type_name(r->type) +
                          (r->count != 1 ? "[" + std::to_string(r->count) + "]" : "") + ", expected " +
                          type_name(type) + (count != 1 ? "[" + std::to_string(count) + "]" : ""));
  if (r->offset + ulog_type_size(type) * count > f.logged_size)
    throw_input_error(
        log.summary.path, 0, field,
        ulog_at_byte(f.byte_offset) + "field lies in the format's trailing padding, which is not logged");
  return r;
}

}  // namespace

std::size_t ulog_type_size(UlogType t) {
  for (const TypeInfo& i : kTypes)
    if (i.type == t) return i.size;
  return 0;
}

std::optional<std::string> UlogSummary::info_value(std::string_view key) const {
  for (const UlogInfo& i : info)
    if (i.key == key) return i.value;
  return std::nullopt;
}

bool is_ulog(std::string_view head) {
  return head.size() >= sizeof kMagic && std::equal(kMagic, kMagic + sizeof kMagic, head.begin());
}

UlogLog parse_ulog(std::string bytes, const std::string& path) {
  return UlogParser(std::move(bytes), path).run();
}

UlogLog read_ulog(const std::string& path) {
  return parse_ulog(read_file_text(path), path);
}

std::optional<UlogFieldRef> find_ulog_field(const UlogLog& log, std::size_t format, std::string_view path) {
  UlogFieldRef r;
  std::uint32_t base = 0;
  while (true) {
    const std::size_t dot = path.find('.');
    const std::string_view name = path.substr(0, dot);
    const UlogFormat& f = log.formats.at(format);
    const auto it =
        std::find_if(f.fields.begin(), f.fields.end(), [&](const UlogField& x) { return x.name == name; });
    if (it == f.fields.end()) return std::nullopt;
    if (dot == std::string_view::npos) {
      r.type = it->type;
      r.offset = base + it->offset;
      r.count = it->count;
      return r;
    }
    if (it->type != UlogType::nested) return std::nullopt;
    base += it->offset;
    format = it->nested;
    path = path.substr(dot + 1);
  }
}

double ulog_number(const UlogLog& log, const UlogDataMessage& m, const UlogFieldRef& f, std::uint32_t index) {
  const std::size_t element = ulog_type_size(f.type);
  const std::size_t offset = f.offset + static_cast<std::size_t>(index) * element;
  if (element == 0 || index >= f.count || offset + element > m.size)
    throw_input_error(log.summary.path, 0, "D " + quote_log_text(log.subscriptions[m.subscription].topic),
                      ulog_at_byte(m.offset) + "a field element at data offset " + std::to_string(offset) +
                          " lies outside the message's " + std::to_string(m.size) + " data bytes");
  const char* p = log.bytes.data() + m.offset + offset;
  switch (f.type) {
    case UlogType::int8:
      return load_i8(p);
    case UlogType::uint8:
    case UlogType::boolean:
    case UlogType::character:
      return load_u8(p);
    case UlogType::int16:
      return load_i16(p);
    case UlogType::uint16:
      return load_u16(p);
    case UlogType::int32:
      return load_i32(p);
    case UlogType::uint32:
      return load_u32(p);
    case UlogType::int64:
      return static_cast<double>(load_i64(p));
    case UlogType::uint64:
      return static_cast<double>(load_u64(p));
    case UlogType::float32:
      return load_f32(p);
    case UlogType::float64:
      return load_f64(p);
    case UlogType::nested:
      break;
  }
  return 0;
}

AttitudeSeries ulog_attitude(const UlogLog& log, AutopilotAttitudeReport* report,
                             std::optional<double> gnss_lag_ms) {
  const std::string& path = log.summary.path;
  AutopilotAttitudeReport rep;
  rep.format = "px4_ulog";
  rep.file_bytes = log.summary.file_bytes;
  rep.truncated_bytes = log.summary.truncated_bytes;

  // GNSS time: the selected receiver (vehicle_gps_position), else the raw one (sensor_gps).
  std::vector<std::size_t> gps = subscriptions_of(log, "vehicle_gps_position");
  rep.gps_message = "vehicle_gps_position";
  if (const auto raw = subscriptions_of(log, "sensor_gps"); message_count(log, gps) == 0 && !raw.empty()) {
    gps = raw;
    rep.gps_message = "sensor_gps";
  }
  if (gps.empty())
    throw_input_error(
        path, 0, "A vehicle_gps_position",
        "the log has neither a vehicle_gps_position nor a sensor_gps topic: its boot time cannot be "
        "mapped to UTC");
  const std::size_t gf = log.subscriptions[gps.front()].format;
  const auto g_ts = *typed_field(log, gf, "timestamp", UlogType::uint64, 1, true);
  const auto g_utc = *typed_field(log, gf, "time_utc_usec", UlogType::uint64, 1, true);
  const auto g_fix = *typed_field(log, gf, "fix_type", UlogType::uint8, 1, true);
  const auto g_rel = typed_field(log, gf, "timestamp_time_relative", UlogType::int32, 1, false);
  std::vector<BootUtcPair> pairs;
  for (const UlogDataMessage& m : log.data) {
    if (std::find(gps.begin(), gps.end(), m.subscription) == gps.end()) continue;
    ++rep.gps_messages;
    const char* p = log.bytes.data() + m.offset;
    const std::uint64_t utc = load_u64(p + g_utc.offset), ts = load_u64(p + g_ts.offset);
    const std::int64_t rel = g_rel ? load_i32(p + g_rel->offset) : 0;
    if (load_u8(p + g_fix.offset) < 3 || utc == 0 || utc > kMaxPlausibleUlogUs || ts > kMaxPlausibleUlogUs) {
      ++rep.gps_skipped;
      continue;
    }
    pairs.push_back({static_cast<std::int64_t>(ts) + rel, UtcTime{static_cast<std::int64_t>(utc) * 1000}});
  }
  rep.gnss_lag_ms = gnss_lag_ms.value_or(kUlogDefaultGnssLagMs);
  rep.gnss_lag_given = gnss_lag_ms.has_value();
  rep.fit = fit_boot_time(std::move(pairs), path, "D " + rep.gps_message + ".time_utc_usec",
                          boot_time_options_for_lag(rep.gnss_lag_ms));

  const std::vector<std::size_t> att = subscriptions_of(log, "vehicle_attitude");
  rep.attitude_message = "vehicle_attitude";
  if (att.empty())
    throw_input_error(path, 0, "A vehicle_attitude",
                      "the log has no vehicle_attitude topic (" + std::to_string(log.summary.topics.size()) +
                          " other topics)");
  const std::size_t af = log.subscriptions[att.front()].format;
  const auto a_q = *typed_field(log, af, "q", UlogType::float32, 4, true);
  const auto a_ts = *typed_field(log, af, "timestamp", UlogType::uint64, 1, true);
  const auto a_sample = typed_field(log, af, "timestamp_sample", UlogType::uint64, 1, false);
  const UlogFieldRef a_time = a_sample ? *a_sample : a_ts;
  rep.attitude_time_field = a_sample ? "timestamp_sample" : "timestamp";

  std::vector<BootAttitudeSample> raw;
  for (const UlogDataMessage& m : log.data) {
    if (std::find(att.begin(), att.end(), m.subscription) == att.end()) continue;
    ++rep.attitude_messages;
    const char* p = log.bytes.data() + m.offset;
    const std::uint64_t t = load_u64(p + a_time.offset);
    double q[4];
    for (int i = 0; i < 4; ++i) q[i] = load_f32(p + a_q.offset + 4 * static_cast<std::size_t>(i));
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    // A logged unit quaternion is unit to float precision (~1e-7); 1e-3 leaves margin and still
    // rejects the zero quaternion an estimator publishes before it is initialised.
    if (t == 0 || t > kMaxPlausibleUlogUs || !(std::abs(norm - 1) <= 1e-3)) {
      ++rep.attitude_invalid;
      continue;
    }
    raw.push_back({static_cast<std::int64_t>(t), attitude_from_quaternion(q[0], q[1], q[2], q[3])});
  }
  return autopilot_attitude_series(
      raw, path, {"D vehicle_attitude", "messages", "not a unit quaternion or without a time"},
      std::move(rep), report);
}

AttitudeSeries read_ulog_attitude(const std::string& path, AutopilotAttitudeReport* report,
                                  std::optional<double> gnss_lag_ms) {
  return ulog_attitude(read_ulog(path), report, gnss_lag_ms);
}

}  // namespace rangecal
