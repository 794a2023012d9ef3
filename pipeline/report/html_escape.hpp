#pragma once
// Text into HTML / SVG (report.html, docs/outputs.md): every piece of text that comes from a file or the
// config (mission, camera ids, warnings, pole ids) goes through html_escape, so it shows as written
// and cannot break the page.
#include <string>
#include <string_view>

namespace rangecal {

/// Escapes & < > " ' for use in element text and in quoted attribute values.
inline std::string html_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace rangecal
