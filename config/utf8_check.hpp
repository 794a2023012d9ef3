#pragma once
// The refusal of input text that is not UTF-8 (docs/reliability.md "Text inputs"): the rule is
// config/text_encoding.hpp's, the error is rangecal::Error (config/error.hpp), whose message is
// itself made printable by that rule.
#include <string>
#include <string_view>

namespace rangecal {

/// Throws rangecal::Error (input) naming `file`, `line` and the column of the first byte of
/// `text` that is not well-formed UTF-8; `what` names the field ("" for a whole line).
void require_utf8(std::string_view text, const std::string& file, long line, const std::string& field);

}  // namespace rangecal
