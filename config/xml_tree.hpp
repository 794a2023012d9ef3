#pragma once
// A small, strict XML reader for header files that carry an XML document (Photron .cihx): enough
// of XML 1.0 for data files, nothing more. Read: the XML declaration and other processing
// instructions (skipped), comments (skipped), elements with attributes (attributes are parsed
// for well-formedness and kept), character data with the five predefined entities and numeric
// character references (&#N; &#xN;), CDATA sections. Refused with a rangecal::Error (input)
// naming the file and line: DOCTYPE declarations, mismatched or unclosed tags, undefined
// entities, control bytes in the document, nesting deeper than kXmlMaxDepth, more than
// kXmlMaxElements elements (memory stays bounded whatever the input), and anything but whitespace,
// comments and processing instructions before the root element.
// Parsing stops at the end of the root element: what follows is the caller's business (PFV
// appends a binary block after the .cihx document).
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace rangecal {

constexpr int kXmlMaxDepth = 64;
constexpr std::size_t kXmlMaxElements = 100000;

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;  ///< in document order
  std::string text;  ///< character data directly inside this element, entities decoded, untrimmed
  long line = 0;     ///< 1-based line of the start tag in the file
  std::vector<XmlElement> children;

  /// The children called `child_name`, in document order.
  std::vector<const XmlElement*> children_named(const std::string& child_name) const;
};

/// Parses the XML document that starts at byte `offset` of `text` (the whole file, so that line
/// numbers count from the file's first byte): optional prolog, then exactly one root element.
/// Returns the root; *end (when given) receives the offset just past the root's end tag.
/// `file` names the file in messages. Throws rangecal::Error (input) on malformed input; the
/// message quotes no raw bytes of the file (names are checked to be ASCII name characters first).
XmlElement parse_xml_document(std::string_view text, std::size_t offset, const std::string& file,
                              std::size_t* end = nullptr);

/// `s` with every byte outside printable ASCII replaced by '?' and cut to `max_chars` (with
/// "..." appended when cut): safe to quote from a file in a message.
std::string printable_excerpt(std::string_view s, std::size_t max_chars = 40);

}  // namespace rangecal
