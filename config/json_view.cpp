#include "config/json_view.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <string_view>

#include "config/text_encoding.hpp"

namespace rangecal {
namespace {

std::string lower(const std::string& s) {
  std::string r = s;
  for (char& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

// Optimal string alignment distance (Levenshtein plus adjacent transpositions): a swapped pair of
// letters is one typo, as people make them.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i)
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

std::string join_quoted(const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", '" : "'") + names[i] + "'";
  return s;
}

}  // namespace

std::string closest_match(const std::string& name, const std::vector<std::string>& candidates) {
  const std::string ln = lower(name);
  const std::size_t limit = std::min<std::size_t>(3, std::max<std::size_t>(1, ln.size() / 3));
  std::string best;
  std::size_t best_d = std::numeric_limits<std::size_t>::max();
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(ln, lower(c));
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best_d <= limit ? best : std::string();
}

std::string did_you_mean(const std::string& name, const std::vector<std::string>& candidates) {
  const std::string m = closest_match(name, candidates);
  return m.empty() ? std::string() : " (did you mean '" + m + "'?)";
}

std::string describe_json(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null:
      return "null";
    case nlohmann::json::value_t::boolean:
      return j.get<bool>() ? "true" : "false";
    case nlohmann::json::value_t::string: {
      std::string s = j.get<std::string>();
      if (s.size() > 40) s = s.substr(0, 37) + "...";
      return "the string \"" + s + "\"";
    }
    case nlohmann::json::value_t::array:
      return "an array of " + std::to_string(j.size()) + (j.size() == 1 ? " element" : " elements");
    case nlohmann::json::value_t::object:
      return "an object";
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned:
    case nlohmann::json::value_t::number_float:
      return "the number " + j.dump();
    default:
      return "an unsupported value";
  }
}

namespace {

// The key path of a value, as JsonView's errors spell it ("a.b[2].c"), built only when an error
// names it: each open container keeps its own step from its parent, so the walk below stays linear
// in the text however deep the nesting (building every container's full path as it opened made a
// 200 KB file of 100,000 nested arrays take 18 GB and two minutes).
struct OpenContainer {
  bool object = false;
  bool expect_key = false;
  std::map<std::string, long> key_lines;  // object: each key and its line (duplicate keys)
  std::string step;                       // from its parent: "key" or "[i]" ("" at the top)
  std::string last_key;                   // object: the key whose value comes next
  std::size_t index = 0;                  // array: the element now being read
};

// The step from the innermost open container to the value being read in it.
std::string value_step(const OpenContainer& c) {
  return c.object ? c.last_key : "[" + std::to_string(c.index) + "]";
}

std::string join_path(std::string path, const std::string& step) {
  if (step.empty()) return path;
  if (path.empty() || step.front() == '[') return path + step;
  return path + "." + step;
}

// The path of the value being read; `max_steps` > 0 keeps only the first and last max_steps / 2
// steps of a longer one, so that a message about deep nesting stays one line.
std::string value_path(const std::vector<OpenContainer>& stack, std::size_t max_steps = 0) {
  std::vector<const std::string*> steps;
  for (const OpenContainer& c : stack)
    if (!c.step.empty()) steps.push_back(&c.step);
  const std::string last = stack.empty() ? std::string() : value_step(stack.back());
  if (!last.empty()) steps.push_back(&last);
  std::string path;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    if (max_steps > 0 && steps.size() > max_steps && k == max_steps / 2) {
      path += "...";
      k = steps.size() - max_steps / 2;
    }
    path = join_path(std::move(path), *steps[k]);
  }
  return path;
}

// One pass over the text: nesting no deeper than kMaxJsonNesting (checked before nlohmann parses,
// since its DOM copy and dump recurse once per level, and a stack overflow is no message), and, when
// `keys_and_numbers`, what nlohmann's DOM parser lets pass or reports without a place: a key given
// twice in one object (nlohmann keeps the last, so a config would be silently ambiguous) and a number
// beyond the range of a double (its out_of_range.406 carries no position). The second check walks
// the text nlohmann has lexed, so strings and numbers are well formed up to the first problem.
void check_json_text(std::string_view text, const std::string& file, ErrorKind kind, bool keys_and_numbers) {
  std::vector<OpenContainer> stack;
  long line = 1;
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (c == '{' || c == '[') {
      if (stack.size() >= kMaxJsonNesting)
        throw Error(kind, file, line, value_path(stack, 8),
                    "arrays and objects nested deeper than " + std::to_string(kMaxJsonNesting) +
                        " levels, refused before parsing; no rangecal file nests more than a few "
                        "(docs/reliability.md \"Bounded work\")");
      OpenContainer o;
      o.object = o.expect_key = c == '{';
      if (!stack.empty()) o.step = value_step(stack.back());
      stack.push_back(std::move(o));
      ++i;
    } else if (c == '}' || c == ']') {
      if (!stack.empty()) stack.pop_back();
      ++i;
    } else if (c == ',') {
      if (!stack.empty() && stack.back().object) stack.back().expect_key = true;
      if (!stack.empty() && !stack.back().object) ++stack.back().index;
      ++i;
    } else if (c == '"') {
      std::size_t j = i + 1;
      while (j < text.size() && text[j] != '"') j += text[j] == '\\' ? 2 : 1;
      if (j >= text.size()) return;  // unterminated: nlohmann reports it
      if (!stack.empty() && stack.back().object && stack.back().expect_key) {
        const std::string_view raw = text.substr(i, j - i + 1);
        std::string key(raw.substr(1, raw.size() - 2));
        if (keys_and_numbers) {
          try {
            key = nlohmann::json::parse(raw).get<std::string>();  // decode escapes: "\u0061" is "a"
          } catch (const nlohmann::json::exception&) {
          }
          const auto [it, inserted] = stack.back().key_lines.emplace(key, line);
          if (!inserted)
            throw Error(kind, file, line, key,
                        "key given twice in the same object (lines " + std::to_string(it->second) + " and " +
                            std::to_string(line) + "); keep one");
        }
        stack.back().expect_key = false;
        stack.back().last_key = std::move(key);
      }
      i = j + 1;
    } else if (keys_and_numbers && (c == '-' || (c >= '0' && c <= '9'))) {
      std::size_t j = i + 1;
      while (j < text.size() && (std::isdigit(static_cast<unsigned char>(text[j])) || text[j] == '.' ||
                                 text[j] == 'e' || text[j] == 'E' || text[j] == '+' || text[j] == '-'))
        ++j;
      const std::string token(text.substr(i, j - i));
      if (!std::isfinite(std::strtod(token.c_str(), nullptr)))
        throw Error(kind, file, line, value_path(stack),
                    "number " + token.substr(0, 40) + " is beyond the range of a double (about ±1.8e308)");
      i = j;
    } else {
      ++i;
    }
  }
}

}  // namespace

nlohmann::json parse_json_text(const std::string& file_text, const std::string& file, ErrorKind kind) {
  const std::string_view text = strip_utf8_bom(file_text);
  check_json_text(text, file, kind, /*keys_and_numbers=*/false);
  try {
    nlohmann::json j = nlohmann::json::parse(text);
    check_json_text(text, file, kind, /*keys_and_numbers=*/true);
    return j;
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is the 1-based offset of the offending character; turn it into line and column.
    const std::size_t byte = std::min<std::size_t>(e.byte, text.size());
    long line = 1;
    std::size_t col = 1;
    for (std::size_t i = 0; i + 1 < byte; ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    std::string what = e.what();
    // nlohmann's message is "[json.exception.parse_error.101] parse error at line L, column C: …";
    // keep the part after the location, which says what was expected.
    const auto colon = what.find(": ", what.find("parse error"));
    if (colon != std::string::npos) what = what.substr(colon + 2);
    throw Error(kind, file, line, "", "invalid JSON at column " + std::to_string(col) + ": " + what);
  } catch (const nlohmann::json::exception& e) {
    check_json_text(text, file, kind, /*keys_and_numbers=*/true);  // names the line of an overflowing number
    throw Error(kind, file, 0, "", std::string("invalid JSON: ") + e.what());
  }
}

void JsonView::fail(const std::string& reason) const {
  throw Error(kind_, file_, 0, path_.empty() ? std::string("(top level)") : path_, reason);
}

void JsonView::fail_expected(const std::string& expected) const {
  fail("expected " + expected + ", got " + describe_json(*j_));
}

const JsonView& JsonView::require_object(const std::string& what) const {
  if (!j_->is_object()) fail_expected(what);
  return *this;
}

void JsonView::check_keys(const std::vector<std::string>& allowed) const {
  require_object();
  for (auto it = j_->begin(); it != j_->end(); ++it) {
    if (std::find(allowed.begin(), allowed.end(), it.key()) != allowed.end()) continue;
    const std::string key_path = path_.empty() ? it.key() : path_ + "." + it.key();
    throw Error(kind_, file_, 0, key_path,
                "unknown key '" + it.key() + "'" + did_you_mean(it.key(), allowed) +
                    "; allowed here: " + join_quoted(allowed));
  }
}

JsonView JsonView::at(const std::string& key, const std::string& expected) const {
  require_object();
  const std::string key_path = path_.empty() ? key : path_ + "." + key;
  const auto it = j_->find(key);
  if (it == j_->end()) throw Error(kind_, file_, 0, key_path, "missing required key; expected " + expected);
  return JsonView(*it, file_, key_path, kind_);
}

std::optional<JsonView> JsonView::find(const std::string& key) const {
  require_object();
  const auto it = j_->find(key);
  if (it == j_->end()) return std::nullopt;
  return JsonView(*it, file_, path_.empty() ? key : path_ + "." + key, kind_);
}

std::size_t JsonView::require_array(const std::string& expected, std::size_t min_size,
                                    std::size_t max_size) const {
  if (!j_->is_array() || j_->size() < min_size || j_->size() > max_size) fail_expected(expected);
  return j_->size();
}

JsonView JsonView::element(std::size_t i) const {
  return JsonView((*j_)[i], file_, path_ + "[" + std::to_string(i) + "]", kind_);
}

double JsonView::number(const std::string& expected) const {
  if (!j_->is_number()) fail_expected(expected);
  const double v = j_->get<double>();
  if (!std::isfinite(v)) fail_expected(expected);
  return v;
}

std::int64_t JsonView::integer(const std::string& expected) const {
  if (j_->is_number_integer()) return j_->get<std::int64_t>();
  if (j_->is_number_unsigned()) {
    const auto u = j_->get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) fail_expected(expected);
    return static_cast<std::int64_t>(u);
  }
  if (j_->is_number_float()) {
    // 1280.0 is an integer written by a tool that prints every number as a float.
    const double v = j_->get<double>();
    if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 9.0e15) return static_cast<std::int64_t>(v);
  }
  fail_expected(expected);
}

std::uint64_t JsonView::unsigned_integer(const std::string& expected) const {
  if (j_->is_number_unsigned()) return j_->get<std::uint64_t>();
  const std::int64_t v = integer(expected);
  if (v < 0) fail_expected(expected);
  return static_cast<std::uint64_t>(v);
}

std::string JsonView::string(const std::string& expected) const {
  if (!j_->is_string()) fail_expected(expected);
  return j_->get<std::string>();
}

std::string JsonView::nonempty_string(const std::string& expected) const {
  std::string s = string(expected);
  if (s.empty()) fail_expected(expected);
  return s;
}

bool JsonView::boolean(const std::string& expected) const {
  if (!j_->is_boolean()) fail_expected(expected);
  return j_->get<bool>();
}

std::vector<double> JsonView::numbers(std::size_t n, const std::string& expected) const {
  if (!j_->is_array() || j_->size() != n) fail_expected(expected);
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& e = (*j_)[i];
    if (!e.is_number() || !std::isfinite(e.get<double>()))
      element(i).fail("expected " + expected + "; element " + std::to_string(i) + " is " + describe_json(e));
    v[i] = e.get<double>();
  }
  return v;
}

}  // namespace rangecal
