#include "vision/frames/photron_cih.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string_view>

#include "config/error.hpp"
#include "config/xml_tree.hpp"

namespace rangecal {
namespace {

namespace fs = std::filesystem;

// A .cihx is tens of kB (the LUT tables make most of it); anything this large is not a header and
// is refused before it is read into memory.
constexpr std::uintmax_t kMaxHeaderBytes = 1u << 20;

struct FieldNames {
  PhotronField field;
  const char* cihx;  // path below <cih>
  const char* cih;   // key of the `Key : Value` line
};

// PFV's names for the fields we read (Photron FASTCAM Viewer .cihx / .cih as saved by PFV 3 and 4).
constexpr FieldNames kFieldNames[] = {
    {PhotronField::width, "imageDataInfo/resolution/width", "Image Width"},
    {PhotronField::height, "imageDataInfo/resolution/height", "Image Height"},
    {PhotronField::color_type, "imageDataInfo/colorInfo/type", "Color Type"},
    {PhotronField::color_bit, "imageDataInfo/colorInfo/bit", "Color Bit"},
    {PhotronField::effective_depth, "imageDataInfo/effectiveBit/depth", "EffectiveBit Depth"},
    {PhotronField::effective_side, "imageDataInfo/effectiveBit/side", "EffectiveBit Side"},
    {PhotronField::file_format, "imageFileInfo/fileFormat", "File Format"},
    {PhotronField::total_frame, "frameInfo/totalFrame", "Total Frame"},
    {PhotronField::start_frame, "frameInfo/startFrame", "Start Frame"},
    {PhotronField::recorded_frame, "frameInfo/recordedFrame", "Original Total Frame"},
    {PhotronField::correct_trigger_frame, "frameInfo/correctTriggerFrame", "Correct Trigger Frame"},
    {PhotronField::skip_frame, "frameInfo/skipFrame", "Save Step"},
    {PhotronField::record_rate, "recordInfo/recordRate", "Record Rate(fps)"},
    {PhotronField::shutter_speed, "recordInfo/shutterSpeed", "Shutter Speed(s)"},
    {PhotronField::shutter_ns, "recordInfo/shutterSpeedNsec", "Shutter Type2(nsec)"},
    {PhotronField::trigger_time, "recordInfo/triggerTime", "Trigger Time"},
    {PhotronField::date, "fileInfo/date", "Date"},
    {PhotronField::time, "fileInfo/time", "Time"},
    {PhotronField::device_name, "deviceInfo/deviceName", "Camera Type"},
    {PhotronField::irig, "deviceInfo/irig", "IRIG"},
    {PhotronField::irig_phase_lock, "deviceInfo/irigPhaseLock", "IRIG Phase Lock"},
};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string trim(std::string_view s) {
  const auto sp = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  std::size_t a = 0, b = s.size();
  while (a < b && sp(s[a])) ++a;
  while (b > a && sp(s[b - 1])) --b;
  return std::string(s.substr(a, b - a));
}

// One field's text as found in the file, with its line for messages.
struct RawField {
  std::string text;
  long line = 0;
};
using RawFields = std::map<PhotronField, RawField>;

RawFields collect_cihx(const std::string& bytes, const std::string& path) {
  // The XML follows a preamble; PFV writes an XML declaration first, a bare <cih> is accepted too.
  std::size_t start = bytes.find("<?xml");
  if (start == std::string::npos) start = bytes.find("<cih");
  if (start == std::string::npos)
    throw_input_error(path, 0, "cih", "no XML document <cih>...</cih> in the file (not a .cihx header?)");
  const XmlElement root = parse_xml_document(bytes, start, path);
  if (root.name != "cih")
    throw_input_error(path, root.line, "cih", "the XML root element is <" + root.name + ">, not <cih>");
  RawFields out;
  for (const FieldNames& f : kFieldNames) {
    const XmlElement* e = &root;
    std::string_view rest = f.cihx;
    while (e && !rest.empty()) {
      const std::size_t slash = rest.find('/');
      const std::string step(rest.substr(0, slash));
      rest = slash == std::string_view::npos ? std::string_view() : rest.substr(slash + 1);
      const auto found = e->children_named(step);
      if (found.size() > 1)
        throw_input_error(path, found[1]->line, f.cihx,
                          "<" + step + "> appears " + std::to_string(found.size()) + " times; expected once");
      e = found.empty() ? nullptr : found[0];
    }
    if (!e) continue;
    if (!e->children.empty())
      throw_input_error(path, e->line, f.cihx, "holds elements; expected a single value");
    const std::string text = trim(e->text);
    if (!text.empty()) out[f.field] = {text, e->line};
  }
  return out;
}

RawFields collect_cih(const std::string& bytes, const std::string& path) {
  std::map<std::string, std::vector<RawField>> lines;
  std::size_t pos = 0;
  long line = 0;
  if (bytes.compare(0, 3, "\xEF\xBB\xBF") == 0) pos = 3;  // a UTF-8 byte order mark
  while (pos < bytes.size()) {
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    const std::string_view l(bytes.data() + pos, eol - pos);
    pos = eol + 1;
    ++line;
    for (char ch : l) {
      const auto c = static_cast<unsigned char>(ch);
      if (c < 0x20 && c != '\t' && c != '\r')
        throw_input_error(path, line, "", "control byte in the file: not a text .cih header");
    }
    const std::string t = trim(l);
    if (t == "END") break;  // PFV appends version and system sections after END
    if (t.empty() || t[0] == '#') continue;
    const std::size_t colon = t.find(':');
    if (colon == std::string::npos)
      throw_input_error(path, line, "", "expected a 'Key : Value' line, got '" + printable_excerpt(t) + "'");
    lines[trim(std::string_view(t).substr(0, colon))].push_back(
        {trim(std::string_view(t).substr(colon + 1)), line});
  }
  if (line == 0) throw_input_error(path, 0, "", "empty file: not a .cih header");
  RawFields out;
  for (const FieldNames& f : kFieldNames) {
    const auto it = lines.find(f.cih);
    if (it == lines.end()) continue;
    if (it->second.size() > 1)
      throw_input_error(path, it->second[1].line, f.cih,
                        "given " + std::to_string(it->second.size()) + " times; expected once");
    if (!it->second[0].text.empty()) out[f.field] = it->second[0];
  }
  return out;
}

// Photron model codes carry the sensor kind as a dash-separated segment: "2100K-M-64GB" is
// monochrome, "…-C-…" colour (Photron product naming).
enum class ModelKind { monochrome, colour, unknown };
ModelKind model_kind(const std::string& device_name) {
  ModelKind kind = ModelKind::unknown;
  std::string seg;
  for (std::size_t i = 0; i <= device_name.size(); ++i) {
    const char c = i < device_name.size() ? device_name[i] : ' ';
    if (c == ' ' || c == '-') {
      if (seg == "M") kind = ModelKind::monochrome;
      if (seg == "C") return ModelKind::colour;
      seg.clear();
    } else {
      seg.push_back(c);
    }
  }
  return kind;
}

class Reader {
 public:
  Reader(const RawFields& raw, PhotronHeader& h) : raw_(raw), h_(h) {}

  const RawField* find(PhotronField f) const {
    const auto it = raw_.find(f);
    return it == raw_.end() ? nullptr : &it->second;
  }
  const RawField& require(PhotronField f) const {
    const RawField* r = find(f);
    if (!r) throw_input_error(h_.path, 0, h_.field(f), "missing required field");
    return *r;
  }
  [[noreturn]] void bad(PhotronField f, const std::string& reason) const {
    const RawField* r = find(f);
    throw_input_error(h_.path, r ? r->line : 0, h_.field(f), reason);
  }
  std::string quoted(PhotronField f) const { return "'" + printable_excerpt(find(f)->text) + "'"; }

  std::int64_t integer(PhotronField f, const RawField& r) const {
    std::int64_t v = 0;
    const char* b = r.text.data();
    const char* e = b + r.text.size();
    const auto res = std::from_chars(b, e, v);
    if (res.ec != std::errc() || res.ptr != e) bad(f, "expected an integer, got " + quoted(f));
    return v;
  }
  std::optional<std::int64_t> opt_integer(PhotronField f) const {
    const RawField* r = find(f);
    if (!r) return std::nullopt;
    return integer(f, *r);
  }
  double number(PhotronField f, std::string_view text) const {
    double v = 0;
    const char* b = text.data();
    const char* e = b + text.size();
    const auto res = std::from_chars(b, e, v);
    if (res.ec != std::errc() || res.ptr != e || !std::isfinite(v))
      bad(f, "expected a number, got " + quoted(f));
    return v;
  }
  std::optional<bool> opt_flag(PhotronField f) const {
    const RawField* r = find(f);
    if (!r) return std::nullopt;
    const std::string v = lower(r->text);
    if (v == "1" || v == "on") return true;
    if (v == "0" || v == "off") return false;
    bad(f, "expected 0/1 or On/Off, got " + quoted(f));
  }

 private:
  const RawFields& raw_;
  PhotronHeader& h_;
};

void fill_header(const RawFields& raw, PhotronHeader& h) {
  const Reader r(raw, h);
  // Size first: everything allocated later is bounded by these.
  for (PhotronField f : {PhotronField::width, PhotronField::height}) {
    const std::int64_t v = r.integer(f, r.require(f));
    if (v < 1 || v > kPhotronMaxDimension)
      r.bad(f, std::to_string(v) + " px is not a possible image size (1…" +
                   std::to_string(kPhotronMaxDimension) + " px)");
    (f == PhotronField::width ? h.width : h.height) = static_cast<int>(v);
  }
  const std::string format = r.require(PhotronField::file_format).text;
  if (lower(format) != "mraw")
    r.bad(PhotronField::file_format, "the frames are stored as " + r.quoted(PhotronField::file_format) +
                                         "; only MRaw recordings are read");

  if (const RawField* d = r.find(PhotronField::device_name)) h.device_name = d->text;
  h.color_type = r.require(PhotronField::color_type).text;
  const std::string ct = lower(h.color_type);
  if (ct == "raw") {
    // Raw sensor data: grey on a monochrome model, a colour-filter mosaic on a colour one.
    const ModelKind kind = model_kind(h.device_name);
    if (kind == ModelKind::colour)
      r.bad(PhotronField::color_type, "Raw data from a colour camera ('" + printable_excerpt(h.device_name) +
                                          "'): colour-mosaic recordings are not supported (record Mono)");
    if (kind == ModelKind::unknown)
      r.bad(PhotronField::color_type, "Raw data, and the camera model (" +
                                          h.field(PhotronField::device_name) + " '" +
                                          printable_excerpt(h.device_name) +
                                          "') does not say monochrome (-M-): cannot tell grey from a colour "
                                          "mosaic; colour is not supported");
  } else if (ct == "color" || ct == "colour" || ct == "rgb" || ct == "bgr" || ct == "bayer") {
    r.bad(PhotronField::color_type,
          "colour recording (" + r.quoted(PhotronField::color_type) +
              "): only monochrome recordings are supported (Mono, or Raw from a monochrome model)");
  } else if (ct != "mono") {
    r.bad(PhotronField::color_type,
          "unknown colour type " + r.quoted(PhotronField::color_type) +
              "; only monochrome recordings are supported (Mono, or Raw from a monochrome model)");
  }

  const std::int64_t bit = r.integer(PhotronField::color_bit, r.require(PhotronField::color_bit));
  if (bit != 8 && bit != 12 && bit != 16)
    r.bad(PhotronField::color_bit,
          "unsupported stored bit depth " + std::to_string(bit) + " (8, 12 packed or 16 are supported)");
  h.color_bit = static_cast<int>(bit);
  const std::int64_t depth =
      r.integer(PhotronField::effective_depth, r.require(PhotronField::effective_depth));
  if (depth < 8 || depth > bit)
    r.bad(PhotronField::effective_depth, "effective depth " + std::to_string(depth) +
                                             " bits does not fit the stored " + std::to_string(bit) +
                                             " bits (8…" + std::to_string(bit) + " supported)");
  h.effective_depth = static_cast<int>(depth);
  const std::string side = lower(r.require(PhotronField::effective_side).text);
  if (side == "lower")
    h.effective_side = EffectiveBitSide::lower;
  else if (side == "higher")
    h.effective_side = EffectiveBitSide::higher;
  else
    r.bad(PhotronField::effective_side,
          "expected Lower or Higher, got " + r.quoted(PhotronField::effective_side));
  if (h.color_bit == 12 &&
      (static_cast<std::uint64_t>(h.width) * static_cast<std::uint64_t>(h.height)) % 2 != 0)
    r.bad(PhotronField::color_bit, "12-bit packed frames need an even pixel count; " +
                                       std::to_string(h.width) + "x" + std::to_string(h.height) + " is odd");

  h.total_frame = r.integer(PhotronField::total_frame, r.require(PhotronField::total_frame));
  if (h.total_frame < 1 || h.total_frame > kPhotronMaxFrames)
    r.bad(PhotronField::total_frame,
          std::to_string(h.total_frame) + " frames; expected 1…" + std::to_string(kPhotronMaxFrames));

  h.start_frame = r.opt_integer(PhotronField::start_frame);
  h.recorded_frame = r.opt_integer(PhotronField::recorded_frame);
  h.correct_trigger_frame = r.opt_integer(PhotronField::correct_trigger_frame);
  h.skip_frame = r.opt_integer(PhotronField::skip_frame);
  if (const RawField* f = r.find(PhotronField::record_rate))
    h.record_rate_fps = r.number(PhotronField::record_rate, f->text);
  // Exposure: the ns field when present; else the shutter speed, which the .cihx writes as the
  // denominator N of 1/N s and the .cih as "1/N" (or plain seconds).
  if (const RawField* f = r.find(PhotronField::shutter_ns)) {
    h.shutter_s = r.number(PhotronField::shutter_ns, f->text) * 1e-9;
  } else if (const RawField* s = r.find(PhotronField::shutter_speed)) {
    const std::string_view t = s->text;
    if (t.rfind("1/", 0) == 0 || h.format == PhotronHeaderFormat::cihx) {
      const double n = r.number(PhotronField::shutter_speed, t.rfind("1/", 0) == 0 ? t.substr(2) : t);
      if (!(n > 0))
        r.bad(PhotronField::shutter_speed,
              "expected a positive 1/N s, got " + r.quoted(PhotronField::shutter_speed));
      h.shutter_s = 1.0 / n;
    } else {
      h.shutter_s = r.number(PhotronField::shutter_speed, t);
    }
  }
  if (const RawField* f = r.find(PhotronField::trigger_time)) h.trigger_time = f->text;
  if (const RawField* f = r.find(PhotronField::date)) h.date = f->text;
  if (const RawField* f = r.find(PhotronField::time)) h.time = f->text;
  h.irig = r.opt_flag(PhotronField::irig);
  h.irig_phase_lock = r.opt_flag(PhotronField::irig_phase_lock);
}

// The value of 1–4 decimal digits; nullopt when empty, longer or not all digits.
std::optional<int> digits(std::string_view s) {
  if (s.empty() || s.size() > 4) return std::nullopt;
  int v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
    v = v * 10 + (c - '0');
  }
  return v;
}

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> out;
  std::size_t a = 0;
  for (;;) {
    const std::size_t b = s.find(sep, a);
    out.push_back(s.substr(a, b == std::string_view::npos ? std::string_view::npos : b - a));
    if (b == std::string_view::npos) return out;
    a = b + 1;
  }
}

}  // namespace

std::string photron_field_name(PhotronHeaderFormat format, PhotronField field) {
  for (const FieldNames& f : kFieldNames)
    if (f.field == field) return format == PhotronHeaderFormat::cihx ? f.cihx : f.cih;
  return "";
}

std::uint64_t PhotronHeader::frame_bytes() const {
  // width, height ≤ 65535 and color_bit ≤ 16: the product stays below 2^37.
  return static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) *
         static_cast<std::uint64_t>(color_bit) / 8;
}

PhotronHeader parse_photron_header(const std::string& bytes, const std::string& path,
                                   PhotronHeaderFormat format) {
  PhotronHeader h;
  h.path = path;
  h.format = format;
  fill_header(format == PhotronHeaderFormat::cihx ? collect_cihx(bytes, path) : collect_cih(bytes, path), h);
  return h;
}

PhotronHeader read_photron_header(const std::string& path) {
  const std::string ext = lower(fs::path(path).extension().string());
  if (ext != ".cihx" && ext != ".cih")
    throw_input_error(path, 0, "", "not a Photron header (expected a .cihx or .cih file)");
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw_input_error(path, 0, "", "missing Photron header file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw_input_error(path, 0, "", "cannot read the size of the header file");
  if (size > kMaxHeaderBytes)
    throw_input_error(path, 0, "",
                      "header file of " + std::to_string(size) +
                          " bytes is too large for a Photron header (limit " +
                          std::to_string(kMaxHeaderBytes) + " bytes)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw_input_error(path, 0, "", "cannot open the Photron header file");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(in.gcount()) != size)
    throw_input_error(path, 0, "", "cannot read the Photron header file");
  return parse_photron_header(bytes, path,
                              ext == ".cihx" ? PhotronHeaderFormat::cihx : PhotronHeaderFormat::cih);
}

std::string find_photron_header(const std::string& mraw_path) {
  const fs::path p(mraw_path);
  std::vector<std::string> tried;
  for (const char* ext : {".cihx", ".CIHX", ".cih", ".CIH"}) {
    fs::path c = p;
    c.replace_extension(ext);
    std::error_code ec;
    if (fs::is_regular_file(c, ec)) return c.string();
    if (ext[1] == 'c') tried.push_back(c.filename().string());
  }
  throw_input_error(mraw_path, 0, "header",
                    "no Photron header beside the .mraw (looked for " + tried[0] + " and " + tried[1] + ")");
}

UtcTime PhotronFrameClock::frame_time(std::int64_t k) const {
  // Camera frame number and its offset from the trigger in ns, in long double (64-bit mantissa:
  // well below 1 ns over any recording photron_frame_clock accepts).
  const long double n = static_cast<long double>(start_frame) + static_cast<long double>(k) * skip_frame;
  return UtcTime{trigger_utc.ns + static_cast<std::int64_t>(std::llroundl(n * 1e9L / record_rate_fps))};
}

PhotronFrameClock photron_frame_clock(const PhotronHeader& h, double clock_utc_offset_h) {
  const std::string instead =
      "; frame times from a Photron header need the date, the time with seconds, the record rate, the start "
      "frame and the save step - otherwise give frames.timestamps, a frame,file,utc CSV naming the .mraw";
  const auto fail = [&](PhotronField f, const std::string& reason) {
    throw_input_error(h.path, 0, h.field(f), reason + instead);
  };
  if (!std::isfinite(clock_utc_offset_h) || std::abs(clock_utc_offset_h) > 14)
    throw_input_error(h.path, 0, "clock_utc_offset_h", "the camera clock's UTC offset must be within ±14 h");
  if (h.date.empty()) fail(PhotronField::date, "missing");
  if (h.time.empty()) fail(PhotronField::time, "missing");
  // Date "Y/M/D" (PFV writes e.g. 2023/1/18).
  const auto dp = split(h.date, '/');
  int y = 0, mo = 0, d = 0;
  bool date_ok = dp.size() == 3;
  if (date_ok) {
    const auto a = digits(dp[0]), b = digits(dp[1]), c = digits(dp[2]);
    date_ok = a && b && c;
    if (date_ok) y = *a, mo = *b, d = *c;
  }
  // UtcTime (int64 ns since 1970) reaches 2262; the years a camera can have recorded in are far inside.
  if (!date_ok || y < 1970 || y > 2200 || !valid_civil_date(y, mo, d))
    fail(PhotronField::date, "'" + printable_excerpt(h.date) + "' is not a date Y/M/D in 1970-2200");
  // Time "h:m:s" with an optional fraction; PFV also writes "h:m", which has no usable second.
  const auto tp = split(h.time, ':');
  if (tp.size() == 2 && digits(tp[0]) && digits(tp[1]))
    fail(PhotronField::time, "'" + printable_excerpt(h.time) + "' has no seconds");
  int hh = 0, mi = 0, ss = 0;
  std::int64_t nanos = 0;
  bool time_ok = tp.size() == 3;
  if (time_ok) {
    const std::size_t dot = tp[2].find('.');
    const auto a = digits(tp[0]), b = digits(tp[1]), c = digits(tp[2].substr(0, dot));
    time_ok = a && b && c;
    if (time_ok) hh = *a, mi = *b, ss = *c;
    if (time_ok && dot != std::string_view::npos) {
      const std::string_view frac = tp[2].substr(dot + 1);
      time_ok = !frac.empty() && frac.size() <= 9 &&
                std::all_of(frac.begin(), frac.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
      for (std::size_t i = 0; time_ok && i < 9; ++i)
        nanos = nanos * 10 + (i < frac.size() ? frac[i] - '0' : 0);
    }
  }
  if (!time_ok || hh > 23 || mi > 59 || ss > 59)
    fail(PhotronField::time, "'" + printable_excerpt(h.time) + "' is not a time h:m:s");
  if (!h.record_rate_fps) fail(PhotronField::record_rate, "missing");
  const double rate = *h.record_rate_fps;
  if (!(rate >= 1e-3) || rate > 1e9)
    fail(PhotronField::record_rate, "must be a frame rate of 0.001…10^9 fps");
  if (!h.start_frame) fail(PhotronField::start_frame, "missing");
  if (!h.skip_frame) fail(PhotronField::skip_frame, "missing");
  if (*h.skip_frame < 1 || *h.skip_frame > 1'000'000'000)
    fail(PhotronField::skip_frame, "save step " + std::to_string(*h.skip_frame) + " is not 1…10^9");
  if (std::llabs(*h.start_frame) > 1'000'000'000'000ll)
    fail(PhotronField::start_frame, "frame number " + std::to_string(*h.start_frame) + " is out of range");

  PhotronFrameClock c;
  const UtcTime clock = utc_from_civil(y, mo, d, hh, mi, ss, nanos);
  c.trigger_utc =
      UtcTime{clock.ns - static_cast<std::int64_t>(std::llround(clock_utc_offset_h * 3600.0 * 1e9))};
  c.start_frame = *h.start_frame;
  c.skip_frame = *h.skip_frame;
  c.record_rate_fps = rate;
  // The last frame must stay within a few years of the trigger (int64 ns never overflows).
  const long double last =
      static_cast<long double>(c.start_frame) +
      static_cast<long double>(h.total_frame - 1) * static_cast<long double>(c.skip_frame);
  if (std::fabs(last * 1e9L / static_cast<long double>(rate)) > 1e17L)
    fail(PhotronField::record_rate,
         "frame times run beyond 3 years from the trigger at " + std::to_string(rate) + " fps");
  return c;
}

}  // namespace rangecal
