#include "config/utf8_check.hpp"

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "config/text_encoding.hpp"

namespace rangecal {

void require_utf8(std::string_view text, const std::string& file, long line, const std::string& field) {
  const auto bad = first_invalid_utf8(text);
  if (!bad) return;
  throw_input_error(file, line, field,
                    fmt::format("byte 0x{:02X}", static_cast<unsigned char>(text[*bad])) + " at column " +
                        std::to_string(*bad + 1) +
                        " is not UTF-8 text (is this a binary file, or text in another encoding?)");
}

}  // namespace rangecal
