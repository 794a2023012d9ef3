#pragma once
// Text-encoding rules for every text input and every message (docs/reliability.md): inputs are
// UTF-8 (ASCII in practice), optionally starting with a byte-order mark, with LF or CRLF line
// ends; messages never carry raw binary bytes to the terminal.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace rangecal {

/// `text` without a leading UTF-8 byte-order mark (EF BB BF), which editors on Windows add.
std::string_view strip_utf8_bom(std::string_view text);

/// Offset of the first byte that does not belong to a well-formed UTF-8 sequence (RFC 3629:
/// no overlong forms, no surrogates, at most U+10FFFF), or nullopt when all of `text` is UTF-8.
std::optional<std::size_t> first_invalid_utf8(std::string_view text);

/// `text` made safe to print: well-formed UTF-8 is kept, tab stays, other control bytes and bytes
/// outside well-formed UTF-8 become `\xNN`.
std::string printable_text(std::string_view text);

}  // namespace rangecal
