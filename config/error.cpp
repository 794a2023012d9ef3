#include "config/error.hpp"

#include "config/text_encoding.hpp"

namespace rangecal {

std::string format_error_message(const std::string& file, long line, const std::string& field,
                                 const std::string& reason) {
  std::string msg;
  if (!file.empty()) {
    msg += file;
    if (line > 0) msg += ":" + std::to_string(line);
    msg += ": ";
  } else if (line > 0) {
    msg += "line " + std::to_string(line) + ": ";
  }
  if (!field.empty()) msg += "field '" + field + "': ";
  msg += reason;
  // File names, fields and quoted values come from user input: never echo raw binary bytes.
  return printable_text(msg);
}

Error::Error(ErrorKind kind, std::string file, long line, std::string field, std::string reason)
    : std::runtime_error(format_error_message(file, line, field, reason)),
      kind_(kind),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)),
      reason_(std::move(reason)) {}

void throw_config_error(const std::string& file, const std::string& json_path, const std::string& reason) {
  throw Error(ErrorKind::usage, file, 0, json_path, reason);
}

void throw_input_error(const std::string& file, long line, const std::string& field,
                       const std::string& reason) {
  throw Error(ErrorKind::input, file, line, field, reason);
}

void throw_calibration_error(const std::string& what, const std::string& reason) {
  throw Error(ErrorKind::calibration, "", 0, what, reason);
}

}  // namespace rangecal
