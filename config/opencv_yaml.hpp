#pragma once
// OpenCV's FileStorage YAML ("%YAML:1.0"), the form cv::FileStorage writes, read without OpenCV's
// own parser. OpenCV 4.6's parser (Debian 12) is not safe on damaged files: it loops forever on a
// damaged document start ("---YAML:1.0" followed by a line like "x---"), recurses once per nesting
// level without limit (a stack overflow, which no exception handler catches) and throws
// std::length_error on some damaged lines (docs/reliability.md "Fuzzing"); its messages carry the
// line only inside their text. This reader is one pass over the text, without recursion: every
// input ends, in linear time, in a document or in a rangecal::Error (input) naming the file, the
// 1-based line and the top-level key.
//
// Read, as cv::FileStorage writes them:
//   - an optional directive "%YAML:1.x" (or "%YAML 1.x") and an optional document start "---",
//     each alone on its line;
//   - a block map at column 0 of `key: value` entries (a key is a letter or '_' followed by
//     letters, digits, '_', '-' or blanks, at most 256 characters; each key once);
//   - values: a scalar on the key's line (plain, or quoted with "..." or '...'); a matrix: an
//     `!!opencv-matrix` (or an untagged map, which cv::FileNode >> Mat reads too) whose indented
//     block holds rows, cols, dt and `data: [ ... ]` (the list may run over several lines; .Inf,
//     -.Inf and .Nan are read as OpenCV writes them; 0 × 0 with [] is an empty matrix); anything
//     else (a nested map or list, a flow collection, another tag) is kept as kind `other`, its lines
//     skipped by indentation or by bracket balance;
//   - blank lines, comment lines ('#'), CRLF line ends, a UTF-8 byte-order mark;
//   - the first document only, as cv::FileStorage's operator[] reads it: a "..." or "---" line
//     ends it (FileStorage::APPEND adds further documents after them).
// Refused: XML and JSON FileStorage files (the first character says which), control bytes, text
// that is not UTF-8, a top level that is a list, an unclosed '[' or '{', a matrix whose data is in
// base64 (FileStorage::BASE64), more than kOpenCvYamlMaxEntries keys, and files larger than
// kOpenCvYamlMaxBytes (gzip-compressed files, which cv::FileStorage also reads, are not text).
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace rangecal {

/// Largest file read_opencv_yaml_file reads (camera files are a few kB; calibration files with
/// every view's image points a few MB), and most top-level keys a document may have: memory stays
/// within a few hundred MB whatever the input.
constexpr std::size_t kOpenCvYamlMaxBytes = std::size_t{16} << 20;
constexpr std::size_t kOpenCvYamlMaxEntries = 100000;

/// One top-level `key: value`.
struct OpenCvYamlEntry {
  enum class Kind { scalar, matrix, other };
  std::string key;
  long line = 0;  ///< 1-based line of `key:`
  Kind kind = Kind::other;
  /// Kind scalar: the value as written, trimmed, quotes removed; in "..." OpenCV's escapes are
  /// decoded (\n \t \r \xHH, and \ before any other character keeps it: \" \' \\).
  std::string scalar;
  /// Kind matrix (`!!opencv-matrix`): rows × cols elements of `channels` values each, row-major,
  /// as doubles whatever the element type `depth` (OpenCV's dt letter: u c w s i f d h).
  int rows = 0;
  int cols = 0;
  int channels = 1;
  char depth = 'd';
  std::vector<double> data;
  long data_line = 0;  ///< 1-based line of `data:`
};

struct OpenCvYamlDocument {
  std::string file;                      ///< as given, for messages
  std::vector<OpenCvYamlEntry> entries;  ///< in file order; keys are unique

  /// The entry called `key`, or nullptr.
  const OpenCvYamlEntry* find(std::string_view key) const;
};

/// Parses `text` (a whole file; `file` names it in messages). Throws rangecal::Error (input)
/// naming the file, line and top-level key of the first thing that is not in the form above.
OpenCvYamlDocument parse_opencv_yaml(std::string_view text, const std::string& file);

/// Reads and parses the file at `path`; a missing file, a directory or a file larger than
/// kOpenCvYamlMaxBytes is an error (input) naming it.
OpenCvYamlDocument read_opencv_yaml_file(const std::string& path);

/// A real number as OpenCV writes one: decimal or exponent form ("1.", "-2.5e-03"), or .Inf,
/// -.Inf, .Nan (any letter case). False when `s` is anything else.
bool parse_opencv_yaml_real(std::string_view s, double* value);

}  // namespace rangecal
