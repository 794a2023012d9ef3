#include "config/xml_tree.hpp"

#include <algorithm>
#include <cstdint>

#include "config/error.hpp"
#include "config/number_format.hpp"

namespace rangecal {

std::vector<const XmlElement*> XmlElement::children_named(const std::string& child_name) const {
  std::vector<const XmlElement*> out;
  for (const XmlElement& c : children)
    if (c.name == child_name) out.push_back(&c);
  return out;
}

std::string printable_excerpt(std::string_view s, std::size_t max_chars) {
  std::string out;
  for (std::size_t i = 0; i < s.size() && i < max_chars; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    out.push_back(c >= 0x20 && c < 0x7F ? static_cast<char>(c) : '?');
  }
  if (s.size() > max_chars) out += "...";
  return out;
}

namespace {

bool is_name_start(unsigned char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == ':';
}
bool is_name_char(unsigned char c) {
  return is_name_start(c) || (c >= '0' && c <= '9') || c == '-' || c == '.';
}
bool is_xml_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

// UTF-8 encoding of a code point already checked to be an XML Char.
void append_utf8(std::string& out, std::uint32_t cp) {
  if (cp < 0x80) {
    out.push_back(static_cast<char>(cp));
  } else if (cp < 0x800) {
    out.push_back(static_cast<char>(0xC0 | (cp >> 6)));
    out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
  } else if (cp < 0x10000) {
    out.push_back(static_cast<char>(0xE0 | (cp >> 12)));
    out.push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
  } else {
    out.push_back(static_cast<char>(0xF0 | (cp >> 18)));
    out.push_back(static_cast<char>(0x80 | ((cp >> 12) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
  }
}

// The XML 1.0 Char production (W3C XML 1.0, §2.2).
bool is_xml_char(std::uint32_t cp) {
  return cp == 0x9 || cp == 0xA || cp == 0xD || (cp >= 0x20 && cp <= 0xD7FF) ||
         (cp >= 0xE000 && cp <= 0xFFFD) || (cp >= 0x10000 && cp <= 0x10FFFF);
}

class XmlParser {
 public:
  XmlParser(std::string_view text, std::size_t offset, const std::string& file)
      : t_(text), pos_(std::min(offset, text.size())), file_(file) {
    line_ =
        1 + static_cast<long>(std::count(t_.begin(), t_.begin() + static_cast<std::ptrdiff_t>(pos_), '\n'));
  }

  XmlElement document(std::size_t* end) {
    // Prolog: whitespace, the XML declaration, processing instructions and comments.
    for (;;) {
      skip_space();
      if (at_end()) fail("no root element");
      if (starts_with("<?")) {
        advance(2);
        skip_past("?>", "processing instruction");
      } else if (starts_with("<!--")) {
        advance(4);
        skip_past("-->", "comment");
      } else if (starts_with("<!")) {
        fail("DOCTYPE and other markup declarations are not supported");
      } else if (t_[pos_] == '<') {
        break;
      } else {
        check_byte(t_[pos_]);
        fail("text before the root element");
      }
    }
    XmlElement root;
    std::vector<XmlElement*> open;  // ancestors stay put: only the innermost element gains children
    if (!start_tag(root)) open.push_back(&root);
    while (!open.empty()) {
      if (at_end())
        fail("element <" + open.back()->name + "> (line " + std::to_string(open.back()->line) +
             ") is not closed");
      const char c = t_[pos_];
      if (c == '&') {
        entity(open.back()->text);
      } else if (c != '<') {
        check_byte(c);
        open.back()->text.push_back(c);
        advance(1);
      } else if (starts_with("</")) {
        advance(2);
        const std::string n = name();
        skip_space();
        expect('>', "'>' to end the end tag </" + n);
        if (n != open.back()->name)
          fail("end tag </" + n + "> does not match <" + open.back()->name + "> (line " +
               std::to_string(open.back()->line) + ")");
        open.pop_back();
      } else if (starts_with("<!--")) {
        advance(4);
        skip_past("-->", "comment");
      } else if (starts_with("<![CDATA[")) {
        advance(9);
        const std::size_t stop = t_.find("]]>", pos_);
        if (stop == std::string_view::npos) fail("CDATA section is not closed");
        while (pos_ < stop) {
          check_byte(t_[pos_]);
          open.back()->text.push_back(t_[pos_]);
          advance(1);
        }
        advance(3);
      } else if (starts_with("<?")) {
        advance(2);
        skip_past("?>", "processing instruction");
      } else if (starts_with("<!")) {
        fail("markup declaration inside an element");
      } else {
        if (static_cast<int>(open.size()) >= kXmlMaxDepth)
          fail("elements nested deeper than " + std::to_string(kXmlMaxDepth) + " levels");
        if (++elements_ > kXmlMaxElements)
          fail("more than " + std::to_string(kXmlMaxElements) + " elements (not a header document)");
        XmlElement* parent = open.back();
        parent->children.emplace_back();
        XmlElement& child = parent->children.back();
        if (!start_tag(child)) open.push_back(&child);
      }
    }
    if (end) *end = pos_;
    return root;
  }

 private:
  [[noreturn]] void fail(const std::string& reason) const { throw_input_error(file_, line_, "XML", reason); }

  bool at_end() const { return pos_ >= t_.size(); }
  bool starts_with(std::string_view s) const { return t_.substr(pos_, s.size()) == s; }
  void advance(std::size_t n) {
    for (std::size_t i = 0; i < n && pos_ < t_.size(); ++i, ++pos_)
      if (t_[pos_] == '\n') ++line_;
  }
  void skip_space() {
    while (!at_end() && is_xml_space(t_[pos_])) advance(1);
  }
  // Bytes below 0x20 other than tab, CR and LF are not XML characters: a binary file, or a
  // header damaged in transfer.
  void check_byte(char ch) const {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 && c != '\t' && c != '\n' && c != '\r') {
      fail(fmt::format("control byte 0x{:02X} in the document (not text XML)", c));
    }
  }
  void expect(char c, const std::string& what) {
    if (at_end() || t_[pos_] != c) fail("expected " + what);
    advance(1);
  }
  void skip_past(std::string_view terminator, const char* what) {
    const std::size_t stop = t_.find(terminator, pos_);
    if (stop == std::string_view::npos) fail(std::string(what) + " is not closed");
    while (pos_ < stop) {
      check_byte(t_[pos_]);
      advance(1);
    }
    advance(terminator.size());
  }
  std::string name() {
    if (at_end()) fail("unexpected end of the document; expected a name");
    const auto first = static_cast<unsigned char>(t_[pos_]);
    if (!is_name_start(first)) fail("expected an element or attribute name (ASCII letter, '_' or ':')");
    const std::size_t start = pos_;
    while (!at_end() && is_name_char(static_cast<unsigned char>(t_[pos_]))) advance(1);
    return std::string(t_.substr(start, pos_ - start));
  }
  // At '&': appends the referenced character(s) to `out`.
  void entity(std::string& out) {
    const std::size_t semi = t_.find(';', pos_);
    if (semi == std::string_view::npos || semi - pos_ > 12)
      fail("malformed entity reference ('&' without ';')");
    const std::string_view ref = t_.substr(pos_ + 1, semi - pos_ - 1);
    if (ref == "lt") {
      out.push_back('<');
    } else if (ref == "gt") {
      out.push_back('>');
    } else if (ref == "amp") {
      out.push_back('&');
    } else if (ref == "quot") {
      out.push_back('"');
    } else if (ref == "apos") {
      out.push_back('\'');
    } else if (ref.size() >= 2 && ref[0] == '#') {
      const bool hex = ref[1] == 'x';
      const std::string_view digits = ref.substr(hex ? 2 : 1);
      if (digits.empty() || digits.size() > 8) fail("malformed character reference");
      std::uint32_t cp = 0;
      for (char d : digits) {
        int v = -1;
        if (d >= '0' && d <= '9') v = d - '0';
        if (hex && d >= 'a' && d <= 'f') v = d - 'a' + 10;
        if (hex && d >= 'A' && d <= 'F') v = d - 'A' + 10;
        if (v < 0) fail("malformed character reference");
        cp = cp * (hex ? 16u : 10u) + static_cast<std::uint32_t>(v);
        if (cp > 0x10FFFF) fail("character reference beyond U+10FFFF");
      }
      if (!is_xml_char(cp)) fail("character reference to a character XML does not allow");
      append_utf8(out, cp);
    } else {
      fail("undefined entity reference (only &lt; &gt; &amp; &quot; &apos; and &#...; are defined)");
    }
    advance(semi + 1 - pos_);
  }
  // At '<' of a start tag: fills e.name, e.attributes, e.line; true when the tag is self-closing.
  bool start_tag(XmlElement& e) {
    e.line = line_;
    advance(1);
    e.name = name();
    for (;;) {
      const std::size_t before = pos_;
      skip_space();
      if (at_end()) fail("start tag <" + e.name + "> is not closed");
      if (t_[pos_] == '>') {
        advance(1);
        return false;
      }
      if (starts_with("/>")) {
        advance(2);
        return true;
      }
      if (pos_ == before) fail("expected whitespace, '>' or '/>' in the start tag <" + e.name + ">");
      std::string key = name();
      for (const auto& [k, v] : e.attributes)
        if (k == key) fail("attribute '" + key + "' given twice in <" + e.name + ">");
      skip_space();
      expect('=', "'=' after attribute '" + key + "' in <" + e.name + ">");
      skip_space();
      if (at_end() || (t_[pos_] != '"' && t_[pos_] != '\''))
        fail("attribute '" + key + "' in <" + e.name + "> has no quoted value");
      const char quote = t_[pos_];
      advance(1);
      std::string value;
      for (;;) {
        if (at_end()) fail("attribute '" + key + "' in <" + e.name + "> is not closed");
        const char c = t_[pos_];
        if (c == quote) break;
        if (c == '<') fail("'<' in the value of attribute '" + key + "' in <" + e.name + ">");
        if (c == '&') {
          entity(value);
          continue;
        }
        check_byte(c);
        value.push_back(c);
        advance(1);
      }
      advance(1);
      e.attributes.emplace_back(std::move(key), std::move(value));
    }
  }

  std::string_view t_;
  std::size_t pos_;
  const std::string& file_;
  long line_ = 1;
  std::size_t elements_ = 1;  // the root
};

}  // namespace

XmlElement parse_xml_document(std::string_view text, std::size_t offset, const std::string& file,
                              std::size_t* end) {
  return XmlParser(text, offset, file).document(end);
}

}  // namespace rangecal
