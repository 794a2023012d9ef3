#include "config/opencv_yaml.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <unordered_map>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "config/text_encoding.hpp"
#include "config/utf8_check.hpp"
#include "config/xml_tree.hpp"

namespace rangecal {

const OpenCvYamlEntry* OpenCvYamlDocument::find(std::string_view key) const {
  for (const OpenCvYamlEntry& e : entries)
    if (e.key == key) return &e;
  return nullptr;
}

bool parse_opencv_yaml_real(std::string_view s, double* value) {
  s = trim(s);
  // OpenCV writes non-finite reals as YAML 1.1 does: .Nan, .Inf, -.Inf.
  if (s.size() >= 4 && s.size() <= 5) {
    std::string lower;
    for (const char c : s) lower.push_back(static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c));
    if (lower == ".nan") return *value = std::numeric_limits<double>::quiet_NaN(), true;
    if (lower == ".inf" || lower == "+.inf") return *value = std::numeric_limits<double>::infinity(), true;
    if (lower == "-.inf") return *value = -std::numeric_limits<double>::infinity(), true;
  }
  const auto v = parse_double(s);
  if (!v) return false;
  *value = *v;
  return true;
}

namespace {

constexpr std::string_view kMatrixTag = "!!opencv-matrix";
constexpr std::size_t kMaxKeyLength = 256;  // keeps keys quotable in messages

bool is_blank(char c) {
  return c == ' ' || c == '\t';
}
bool is_space(char c) {
  return is_blank(c) || c == '\r' || c == '\n';
}
bool is_key_start(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_';
}
bool is_key_char(char c) {
  return is_key_start(c) || (c >= '0' && c <= '9') || c == '-';
}
bool starts_with(std::string_view s, std::string_view p) {
  return s.substr(0, p.size()) == p;
}
bool is_list_item(std::string_view body) {
  return body == "-" || starts_with(body, "- ");
}

/// `s` without a trailing comment ('#' at the start or after a blank, outside quotes), trimmed.
std::string_view without_comment(std::string_view s) {
  char quote = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    const bool after_blank = i == 0 || is_blank(s[i - 1]);
    if (quote) {
      if (c == '\\' && quote == '"')
        ++i;
      else if (c == quote)
        quote = 0;
    } else if ((c == '"' || c == '\'') &&
               (after_blank || s[i - 1] == '[' || s[i - 1] == '{' || s[i - 1] == ',')) {
      quote = c;
    } else if (c == '#' && after_blank) {
      return trim(s.substr(0, i));
    }
  }
  return trim(s);
}

/// One line of the file: `indent` blanks, then `body` (trailing blanks and the CR of CRLF removed).
struct Line {
  long number = 0;
  std::size_t indent = 0;
  std::string_view body;
  bool blank_or_comment() const { return body.empty() || body.front() == '#'; }
};

class YamlParser {
 public:
  YamlParser(std::string_view text, const std::string& file) : t_(strip_utf8_bom(text)), file_(file) {}

  OpenCvYamlDocument document() {
    check_text();
    OpenCvYamlDocument doc;
    doc.file = file_;
    preamble();
    std::unordered_map<std::string, long> seen;
    Line l;
    while (next_content(&l)) {
      if (l.indent > 0)
        fail(l.number, doc.entries.empty() ? "" : doc.entries.back().key,
             "an indented line where a top-level 'key: value' was expected");
      // The first document is the one read, as cv::FileStorage's operator[] reads it; a file written
      // with FileStorage::APPEND continues with "...", "---" and another document.
      if (without_comment(l.body) == "..." || without_comment(l.body) == "---") break;
      if (l.body.front() == '-')
        fail(l.number, "", "the top level is a list, not a map of keys (image_width, camera_matrix, ...)");
      if (doc.entries.size() == kOpenCvYamlMaxEntries)
        fail(l.number, "", "more than " + std::to_string(kOpenCvYamlMaxEntries) + " top-level keys");
      take();
      OpenCvYamlEntry e = entry(l);
      const auto [it, fresh] = seen.emplace(e.key, e.line);
      if (!fresh)
        fail(e.line, e.key,
             "appears twice (lines " + std::to_string(it->second) + " and " + std::to_string(e.line) + ")");
      doc.entries.push_back(std::move(e));
    }
    if (doc.entries.empty()) fail(0, "", "no 'key: value' entries: an empty OpenCV YAML document");
    return doc;
  }

 private:
  std::string_view t_;
  const std::string& file_;
  std::size_t pos_ = 0;  // offset of the next unread line
  long line_ = 1;        // its 1-based number

  [[noreturn]] void fail(long line, const std::string& field, const std::string& reason) const {
    throw_input_error(file_, line, field, reason);
  }

  std::size_t offset_of(std::string_view inside) const {
    return static_cast<std::size_t>(inside.data() - t_.data());
  }

  // Control bytes (other than tab, and CR before LF) and bytes outside UTF-8 are refused up front,
  // so that every later message can quote the text.
  // Whichever comes first is reported.
  void check_text() const {
    const std::size_t not_utf8 = first_invalid_utf8(t_).value_or(t_.size());
    long line = 1;
    std::size_t line_start = 0;
    for (std::size_t i = 0; i < t_.size(); ++i) {
      const auto c = static_cast<unsigned char>(t_[i]);
      if (i == not_utf8)  // the whole line, so that the column is right
        require_utf8(t_.substr(line_start, t_.find('\n', i) - line_start), file_, line, "");
      if (c == '\n') {
        ++line;
        line_start = i + 1;
      } else if ((c < 0x20 && c != '\t' && !(c == '\r' && i + 1 < t_.size() && t_[i + 1] == '\n')) ||
                 c == 0x7F) {
        fail(line, "", fmt::format("control byte 0x{:02X} (not a text file)", c));
      }
    }
  }

  // The line at the cursor, not consumed; false at the end of the text.
  bool peek(Line* l) const {
    if (pos_ >= t_.size()) return false;
    std::size_t end = t_.find('\n', pos_);
    if (end == std::string_view::npos) end = t_.size();
    std::string_view s = t_.substr(pos_, end - pos_);
    l->number = line_;
    l->indent = 0;
    while (l->indent < s.size() && is_blank(s[l->indent])) ++l->indent;
    s.remove_prefix(l->indent);
    while (!s.empty() && (is_blank(s.back()) || s.back() == '\r')) s.remove_suffix(1);
    l->body = s;
    return true;
  }

  // Consumes the line at the cursor.
  void take() {
    const std::size_t end = t_.find('\n', pos_);
    pos_ = end == std::string_view::npos ? t_.size() : end + 1;
    ++line_;
  }

  // Skips blank and comment lines; `l` receives the next other line (not consumed).
  bool next_content(Line* l) {
    while (peek(l)) {
      if (!l->blank_or_comment()) return true;
      take();
    }
    return false;
  }

  static bool is_yaml_directive(std::string_view b) {
    for (const std::string_view p : {std::string_view("%YAML:1."), std::string_view("%YAML 1.")}) {
      if (!starts_with(b, p) || b.size() == p.size()) continue;
      bool digits = true;
      for (const char c : b.substr(p.size())) digits = digits && c >= '0' && c <= '9';
      if (digits) return true;
    }
    return false;
  }

  // "%YAML:1.0" and "---", each optional and alone on its line.
  void preamble() {
    Line l;
    if (!next_content(&l)) return;
    if (l.body.front() == '<')
      fail(l.number, "",
           "an XML document; OpenCV files are read in YAML only (cv::FileStorage writes YAML to a name "
           "ending in .yml or .yaml)");
    if (l.body.front() == '{')
      fail(l.number, "",
           "a JSON document; OpenCV files are read in YAML only (cv::FileStorage writes YAML to a name "
           "ending in .yml or .yaml)");
    if (l.body.front() == '%') {
      if (l.indent > 0 || !is_yaml_directive(without_comment(l.body)))
        fail(l.number, "", "unsupported directive '" + printable_excerpt(l.body) + "'; expected %YAML:1.0");
      take();
      if (!next_content(&l)) return;
    }
    if (starts_with(l.body, "---")) {
      if (l.indent > 0 || without_comment(l.body) != "---")
        fail(l.number, "",
             "'" + printable_excerpt(l.body) +
                 "': text after the document start '---' (cv::FileStorage writes it alone on its line)");
      take();
    }
  }

  // `key: value` on line `l`: returns the key and sets *value (comment removed, trimmed). Errors
  // name `field`, or the key itself when `field` is empty.
  std::string_view key_and_value(const Line& l, const std::string& field, std::string_view* value) const {
    const std::string_view b = l.body;
    if (!is_key_start(b.front()))
      fail(l.number, field,
           "expected 'key: value', got '" + printable_excerpt(b) + "' (a key starts with a letter or '_')");
    // cv::FileStorage's writer allows letters, digits, '_', '-' and ' ' in a key.
    std::size_t k = 1;
    while (k < b.size() && (is_key_char(b[k]) || b[k] == ' ')) ++k;
    while (b[k - 1] == ' ') --k;
    if (k > kMaxKeyLength)
      fail(l.number, field,
           "a key of more than " + std::to_string(kMaxKeyLength) + " characters: '" + printable_excerpt(b) +
               "'");
    const std::string key(b.substr(0, k));
    const std::string& f = field.empty() ? key : field;
    std::size_t c = k;
    while (c < b.size() && is_blank(b[c])) ++c;
    if (c == b.size() || b[c] != ':')
      fail(l.number, f, "expected ':' after the key '" + key + "', got '" + printable_excerpt(b) + "'");
    ++c;
    if (c < b.size() && !is_blank(b[c]))
      fail(l.number, f, "expected a blank after '" + key + ":', got '" + printable_excerpt(b) + "'");
    *value = without_comment(b.substr(c));
    return b.substr(0, k);
  }

  OpenCvYamlEntry entry(const Line& l) {
    OpenCvYamlEntry e;
    e.line = l.number;
    std::string_view value;
    e.key = std::string(key_and_value(l, "", &value));
    if (value == kMatrixTag) {
      matrix(&e);
      return e;
    }
    if (starts_with(value, "!")) {  // another tag: its value, if any, is skipped
      const std::size_t blank = value.find_first_of(" \t");
      value = blank == std::string_view::npos ? std::string_view() : trim(value.substr(blank));
    }
    if (value.empty() && untagged_matrix_follows()) {  // cv::FileNode >> Mat does not need the tag
      matrix(&e);
      return e;
    }
    if (value.empty() || value.front() == '|' || value.front() == '>') {  // a nested block, a block scalar
      skip_block();
      return e;
    }
    if (value.front() == '[' || value.front() == '{') {
      skip_flow(e.key, value, l.number);
      return e;
    }
    e.kind = OpenCvYamlEntry::Kind::scalar;
    e.scalar = scalar_text(value, l.number, e.key);
    Line next;
    if (next_content(&next) && next.indent > 0)
      fail(next.number, e.key,
           "an indented line after the value of '" + e.key + "' (line " + std::to_string(e.line) + ")");
    return e;
  }

  // Whether the nested block that follows is a matrix without its tag: its keys (the lines at the
  // block's own indentation) are only rows, cols, dt and data, with dt and data among them. The
  // lines are looked at, not consumed.
  bool untagged_matrix_follows() const {
    bool dt = false, data = false;
    std::size_t indent = 0;
    for (std::size_t at = pos_; at < t_.size();) {
      std::size_t end = t_.find('\n', at);
      if (end == std::string_view::npos) end = t_.size();
      std::string_view s = t_.substr(at, end - at);
      at = end + 1;
      std::size_t i = 0;
      while (i < s.size() && is_blank(s[i])) ++i;
      s.remove_prefix(i);
      if (trim(s).empty() || s.front() == '#') continue;
      if (i == 0) break;
      if (indent == 0) indent = i;
      if (i != indent) continue;  // a continuation line of the data list
      bool known = false;
      for (const std::string_view k : {"rows", "cols", "dt", "data"})
        if (starts_with(s, k) && s.size() > k.size() && (s[k.size()] == ':' || is_blank(s[k.size()]))) {
          known = true;
          dt = dt || k == "dt";
          data = data || k == "data";
        }
      if (!known) return false;
    }
    return dt && data;
  }

  // The lines of a nested map or list: indented, or list items at column 0 (YAML's compact form).
  void skip_block() {
    Line l;
    while (peek(&l) && (l.blank_or_comment() || l.indent > 0 || is_list_item(l.body))) take();
  }

  std::string scalar_text(std::string_view v, long line, const std::string& key) const {
    const char q = v.front();
    if (q != '"' && q != '\'') return std::string(v);
    std::string out;
    for (std::size_t i = 1; i < v.size(); ++i) {
      const char c = v[i];
      if (c == q && q == '\'' && i + 1 < v.size() && v[i + 1] == '\'') {  // '' inside '...'
        out.push_back(c);
        ++i;
      } else if (c == q) {
        if (i + 1 != v.size())
          fail(line, key, "text after the closing quote: '" + printable_excerpt(v.substr(i + 1)) + "'");
        return out;
      } else if (q == '"' && c == '\\' && i + 1 < v.size()) {
        // OpenCV's escapes: \n \t \r, \xHH, and a backslash before any other character keeps
        // that character (\" \' \\).
        const char x = v[++i];
        const auto hex = [](char h) {
          return h >= '0' && h <= '9'   ? h - '0'
                 : h >= 'a' && h <= 'f' ? h - 'a' + 10
                 : h >= 'A' && h <= 'F' ? h - 'A' + 10
                                        : -1;
        };
        if (x == 'n' || x == 't' || x == 'r') {
          out.push_back(x == 'n' ? '\n' : x == 't' ? '\t' : '\r');
        } else if (x == 'x' && i + 2 < v.size() && hex(v[i + 1]) >= 0 && hex(v[i + 2]) >= 0) {
          out.push_back(static_cast<char>(16 * hex(v[i + 1]) + hex(v[i + 2])));
          i += 2;
        } else {
          out.push_back(x);
        }
      } else {
        out.push_back(c);
      }
    }
    fail(line, key, "a quoted value without its closing quote on the same line");
  }

  // Moves the cursor to the line after offset `o` (on line `line`), whose rest must be blank or a
  // comment.
  void finish_line_at(std::size_t o, long line, const std::string& key) {
    std::size_t end = t_.find('\n', o);
    if (end == std::string_view::npos) end = t_.size();
    const std::string_view rest = without_comment(t_.substr(o, end - o));
    if (!rest.empty()) fail(line, key, "text after the closing bracket: '" + printable_excerpt(rest) + "'");
    pos_ = end == t_.size() ? end : end + 1;
    line_ = line + 1;
  }

  // A flow collection ('[' or '{' at the start of `value`, on `line`), skipped to its closing
  // bracket by counting brackets outside quotes: no recursion, whatever the nesting.
  void skip_flow(const std::string& key, std::string_view value, long line) {
    std::size_t depth = 0;
    char quote = 0;
    long ln = line;
    for (std::size_t i = offset_of(value); i < t_.size(); ++i) {
      const char c = t_[i];
      if (c == '\n') {
        ++ln;
      } else if (quote) {
        if (c == '\\' && quote == '"' && i + 1 < t_.size() && t_[i + 1] != '\n')
          ++i;
        else if (c == quote)
          quote = 0;
      } else if ((c == '"' || c == '\'') && (is_space(t_[i - 1]) || t_[i - 1] == '[' || t_[i - 1] == '{' ||
                                             t_[i - 1] == ',' || t_[i - 1] == ':')) {
        quote = c;  // a quote opens only where a value starts (an apostrophe inside a word does not)
      } else if (c == '#' && is_space(t_[i - 1])) {
        while (i + 1 < t_.size() && t_[i + 1] != '\n') ++i;
      } else if (c == '[' || c == '{') {
        ++depth;
      } else if ((c == ']' || c == '}') && --depth == 0) {
        finish_line_at(i + 1, ln, key);
        return;
      }
    }
    fail(line, key,
         std::string("the '") + value.front() + "' opened on line " + std::to_string(line) +
             (quote ? " is never closed (a quote inside it is open)" : " is never closed"));
  }

  static int channel_count(std::string_view digits) {
    if (digits.empty()) return 1;
    if (digits.size() > 3) return 0;
    int n = 0;
    for (const char c : digits) {
      if (c < '0' || c > '9') return 0;
      n = 10 * n + (c - '0');
    }
    return n;
  }

  void element_type(std::string_view v, long line, OpenCvYamlEntry* e) const {
    std::string_view s = v;
    if (s.size() >= 2 && (s.front() == '"' || s.front() == '\'') && s.back() == s.front())
      s = s.substr(1, s.size() - 2);
    // OpenCV's dt: an optional channel count (1 to 512, CV_CN_MAX) and one depth letter.
    const int cn = s.empty() ? 0 : channel_count(s.substr(0, s.size() - 1));
    if (s.empty() || std::string_view("ucwsifdh").find(s.back()) == std::string_view::npos || cn < 1 ||
        cn > 512)
      fail(line, e->key,
           "dt: '" + printable_excerpt(v) +
               "' is not an OpenCV element type (one of u c w s i f d h, after an optional channel count)");
    e->depth = s.back();
    e->channels = cn;
  }

  // The values of `data: [ ... ]` ('[' at the start of `value`, on `line`), one number per
  // comma-separated item, over as many lines as it takes.
  void read_data(std::string_view value, long line, OpenCvYamlEntry* e) {
    long ln = line, item_line = line;
    std::size_t item = 0, item_end = 0;  // offsets of the current item's text; item == 0: none yet
    bool after_comma = false;
    for (std::size_t i = offset_of(value) + 1; i < t_.size(); ++i) {
      const char c = t_[i];
      if (c == '\n') {
        ++ln;
      } else if (is_space(c)) {
        continue;
      } else if (c == '#' && is_space(t_[i - 1])) {
        while (i + 1 < t_.size() && t_[i + 1] != '\n') ++i;
      } else if (c == ',' || c == ']') {
        if (item == 0) {
          if (c == ']' && !after_comma && e->data.empty()) {  // "[ ]"
            finish_line_at(i + 1, ln, e->key);
            return;
          }
          fail(ln, e->key, "data: an empty value (two commas, or a comma before ']' or after '[')");
        }
        double x = 0;
        const std::string_view text = t_.substr(item, item_end - item);
        if (!parse_opencv_yaml_real(text, &x))
          fail(item_line, e->key, "data: '" + printable_excerpt(text) + "' is not a number");
        e->data.push_back(x);
        item = 0;
        after_comma = c == ',';
        if (c == ']') {
          finish_line_at(i + 1, ln, e->key);
          return;
        }
      } else if (c == '[' || c == '{') {
        fail(ln, e->key, "data: a nested list; a matrix's data is a flat list of numbers");
      } else if (item != 0 && item_end != i) {
        fail(ln, e->key,
             "data: expected ',' between values, got '" + printable_excerpt(t_.substr(i, 20)) + "'");
      } else {
        if (item == 0) item = i, item_line = ln;
        item_end = i + 1;
      }
    }
    fail(line, e->key, "data: the '[' opened on line " + std::to_string(line) + " is never closed");
  }

  // The indented block of an !!opencv-matrix: rows, cols, dt and data, each once.
  void matrix(OpenCvYamlEntry* e) {
    e->kind = OpenCvYamlEntry::Kind::matrix;
    bool have[4] = {false, false, false, false};
    static constexpr const char* kKeys[4] = {"rows", "cols", "dt", "data"};
    Line l;
    while (next_content(&l) && l.indent > 0) {
      take();
      std::string_view v;
      const std::string_view k = key_and_value(l, e->key, &v);
      int which = 0;
      while (which < 4 && k != kKeys[which]) ++which;
      if (which == 4)
        fail(l.number, e->key,
             "unexpected key '" + std::string(k) + "' in an !!opencv-matrix (expected rows, cols, dt, data)");
      if (have[which]) fail(l.number, e->key, "'" + std::string(k) + "' appears twice in the matrix");
      have[which] = true;
      if (which <= 1) {
        const auto n = parse_int64(v);
        if (!n || *n < 0 || *n > std::numeric_limits<int>::max())  // 0 × 0: an empty cv::Mat
          fail(l.number, e->key,
               std::string(k) + ": '" + printable_excerpt(v) + "' is not a non-negative integer");
        (which == 0 ? e->rows : e->cols) = static_cast<int>(*n);
      } else if (which == 2) {
        element_type(v, l.number, e);
      } else {
        if (starts_with(v, "!!binary"))
          fail(
              l.number, e->key,
              "data in base64 (written with FileStorage::BASE64) is not read; write the file without BASE64");
        if (v.empty() || v.front() != '[')
          fail(l.number, e->key,
               "data: expected a list '[ ... ]' of numbers, got '" + printable_excerpt(v) + "'");
        e->data_line = l.number;
        read_data(v, l.number, e);
      }
    }
    for (int i = 0; i < 4; ++i)
      if (!have[i])
        fail(e->line, e->key,
             std::string("an !!opencv-matrix needs rows, cols, dt and data; '") + kKeys[i] + "' is missing");
    // rows, cols ≤ n keeps the product within 64 bits (n is bounded by the file's size).
    const std::uint64_t n = e->data.size();
    const auto rows = static_cast<std::uint64_t>(e->rows), cols = static_cast<std::uint64_t>(e->cols);
    if (rows > n || cols > n || rows * cols * static_cast<std::uint64_t>(e->channels) != n)
      fail(e->data_line, e->key,
           "data has " + std::to_string(n) + " values; rows × cols × channels = " + std::to_string(e->rows) +
               " × " + std::to_string(e->cols) + " × " + std::to_string(e->channels));
  }
};

}  // namespace

OpenCvYamlDocument parse_opencv_yaml(std::string_view text, const std::string& file) {
  return YamlParser(text, file).document();
}

OpenCvYamlDocument read_opencv_yaml_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw_input_error(path, 0, "", "file not found");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw_input_error(path, 0, "", "cannot read the file's size: " + ec.message());
  if (size > kOpenCvYamlMaxBytes)
    throw_input_error(path, 0, "",
                      std::to_string(size) + " bytes; an OpenCV YAML file of more than " +
                          std::to_string(kOpenCvYamlMaxBytes >> 20) + " MiB is not read");
  return parse_opencv_yaml(read_file_text(path), path);
}

}  // namespace rangecal
