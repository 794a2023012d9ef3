#pragma once
// Strict, path-aware reading of JSON documents (mission config, calibration.json, scenarios).
// A JsonView is a node plus where it is (file, JSON path such as `cameras[1].sensor`) and the
// error kind to raise; every accessor that finds something wrong throws rangecal::Error naming
// the file, the JSON path, the problem and the expected form, e.g.
//   mission.json: field 'cameras[1].sensor.pixel_size_um': expected an array of 2 positive
//   numbers (µm), got an array of 3 elements
// Unknown keys are errors with a "did you mean 'x'?" suggestion for near-misses.
#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "config/error.hpp"

namespace rangecal {

/// The candidate closest to `name` by edit distance (case-insensitive, transpositions count 1),
/// or "" when none is close enough to be a plausible typo (distance ≤ max(1, len/3), at most 3).
std::string closest_match(const std::string& name, const std::vector<std::string>& candidates);

/// " (did you mean 'x'?)" when `name` is a near miss of a candidate, else "".
std::string did_you_mean(const std::string& name, const std::vector<std::string>& candidates);

/// Short description of a JSON value for messages: `the string "abc"`, `the number -5`,
/// `an array of 3 elements`, `an object`, `null`, `true`.
std::string describe_json(const nlohmann::json& j);

/// How deep arrays and objects may nest in any JSON file rangecal reads (its own files nest at most
/// nine levels, run.json). Deeper text is refused before it is parsed, in one pass over the text:
/// nlohmann's DOM copy, comparison and dump recurse once per level, so a small file of 100,000
/// nested arrays would overflow the stack (docs/reliability.md "Bounded work").
inline constexpr std::size_t kMaxJsonNesting = 64;

/// Parses JSON text; a syntax error throws `kind` naming the file, the line and the column; nesting
/// beyond kMaxJsonNesting, a key given twice in one object and a number beyond a double are
/// refused the same way.
nlohmann::json parse_json_text(const std::string& text, const std::string& file, ErrorKind kind);

class JsonView {
 public:
  JsonView(const nlohmann::json& j, std::string file, std::string path, ErrorKind kind)
      : j_(&j), file_(std::move(file)), path_(std::move(path)), kind_(kind) {}

  const nlohmann::json& json() const { return *j_; }
  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }

  /// Throws kind_ naming this node's path.
  [[noreturn]] void fail(const std::string& reason) const;
  /// Throws "expected <expected>, got <description of the value>".
  [[noreturn]] void fail_expected(const std::string& expected) const;

  // Objects ------------------------------------------------------------------------------------
  /// Requires an object; `what` describes it for the message (e.g. "an object {\"lat\", …}").
  const JsonView& require_object(const std::string& what = "an object") const;
  /// Every key must be in `allowed`; otherwise "unknown key 'x' (did you mean 'y'?); allowed: …".
  void check_keys(const std::vector<std::string>& allowed) const;
  bool has(const std::string& key) const { return j_->is_object() && j_->contains(key); }
  /// A required member; missing → "missing required key; expected <expected>".
  JsonView at(const std::string& key, const std::string& expected) const;
  /// An optional member (nullopt when absent).
  std::optional<JsonView> find(const std::string& key) const;

  // Arrays -------------------------------------------------------------------------------------
  /// Requires an array with size in [min_size, max_size]; `expected` describes it.
  std::size_t require_array(const std::string& expected, std::size_t min_size = 0,
                            std::size_t max_size = static_cast<std::size_t>(-1)) const;
  /// Element i of an array (path `…[i]`).
  JsonView element(std::size_t i) const;

  // Scalars (the `expected` text completes "expected …", e.g. "a positive number (mm)") ---------
  double number(const std::string& expected) const;         ///< any finite number
  std::int64_t integer(const std::string& expected) const;  ///< an integer-valued number
  std::uint64_t unsigned_integer(const std::string& expected) const;
  std::string string(const std::string& expected) const;  ///< a string (may be empty)
  std::string nonempty_string(const std::string& expected) const;
  bool boolean(const std::string& expected) const;
  /// An array of exactly n finite numbers.
  std::vector<double> numbers(std::size_t n, const std::string& expected) const;

 private:
  const nlohmann::json* j_;
  std::string file_;
  std::string path_;
  ErrorKind kind_;
};

}  // namespace rangecal
