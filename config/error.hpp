#pragma once
// The one project error type. Every failure a user can cause (bad usage, bad config, bad or
// insufficient input data, a calibration that cannot be determined) is thrown as rangecal::Error,
// carrying where it happened (file, line, field) and why; the CLI maps its kind to an exit code
// (docs/cli.md: 2 usage/config, 3 input data, 4 calibration failed or degenerate).
#include <stdexcept>
#include <string>

namespace rangecal {

enum class ErrorKind : int {
  usage = 2,        ///< bad command line or mission config (exit 2)
  input = 3,        ///< bad or insufficient input data: files, lines, fields (exit 3)
  calibration = 4,  ///< calibration failed or geometry is degenerate (exit 4)
};

class Error : public std::runtime_error {
 public:
  /// file: path of the offending file (may be empty); line: 1-based line number, 0 when not
  /// applicable; field: column name or JSON path (may be empty); reason: what is wrong and, where
  /// useful, what was expected.
  Error(ErrorKind kind, std::string file, long line, std::string field, std::string reason);

  ErrorKind kind() const { return kind_; }
  int exit_code() const { return static_cast<int>(kind_); }
  const std::string& file() const { return file_; }
  long line() const { return line_; }
  const std::string& field() const { return field_; }
  const std::string& reason() const { return reason_; }

 private:
  ErrorKind kind_;
  std::string file_;
  long line_;
  std::string field_;
  std::string reason_;
};

/// Formats "file:line: field 'f': reason", leaving out the parts that are empty; bytes that are not
/// printable UTF-8 appear as \xNN.
std::string format_error_message(const std::string& file, long line, const std::string& field,
                                 const std::string& reason);

/// Shorthands.
[[noreturn]] void throw_config_error(const std::string& file, const std::string& json_path,
                                     const std::string& reason);
[[noreturn]] void throw_input_error(const std::string& file, long line, const std::string& field,
                                    const std::string& reason);
[[noreturn]] void throw_calibration_error(const std::string& what, const std::string& reason);

}  // namespace rangecal
