// The text rules every input shares (config/text_encoding.hpp, config/csv_table.hpp,
// config/json_view.hpp): CRLF and a byte-order mark accepted, bytes that are not UTF-8 refused
// with their line and column, a JSON key given twice or a number beyond a double refused with its
// line, and messages that never carry raw bytes.
#include <gtest/gtest.h>

#include <chrono>
#include <tuple>
#include <vector>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/json_format.hpp"
#include "config/json_view.hpp"
#include "config/text_encoding.hpp"

namespace rangecal {
namespace {

Error csv_error(const std::string& text) {
  try {
    parse_csv(text, "t.csv");
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error";
  return Error(ErrorKind::usage, "", 0, "", "");
}

Error json_error(const std::string& text) {
  try {
    parse_json_text(text, "m.json", ErrorKind::usage);
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error";
  return Error(ErrorKind::usage, "", 0, "", "");
}

TEST(TextEncoding, Utf8ValidationFollowsRfc3629) {
  EXPECT_FALSE(first_invalid_utf8("plain ASCII, µm, 30°, 北京"));
  EXPECT_EQ(first_invalid_utf8("ab\xff"), 2u);
  EXPECT_EQ(first_invalid_utf8("a\xc0\xaf"), 1u);         // overlong '/'
  EXPECT_EQ(first_invalid_utf8("x\xed\xa0\x80"), 1u);     // surrogate U+D800
  EXPECT_EQ(first_invalid_utf8("\xf4\x90\x80\x80"), 0u);  // beyond U+10FFFF
  EXPECT_EQ(first_invalid_utf8("ok\xe2\x82"), 2u);        // truncated sequence
  EXPECT_EQ(strip_utf8_bom("\xEF\xBB\xBFid,u,v"), "id,u,v");
  EXPECT_EQ(strip_utf8_bom("id,u,v"), "id,u,v");
}

TEST(TextEncoding, PrintableTextEscapesControlAndInvalidBytes) {
  EXPECT_EQ(printable_text("pole P\xff\x1b[31m µm"), "pole P\\xFF\\x1B[31m µm");
  EXPECT_EQ(printable_text(std::string("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(printable_text("tab\tand\nnewline"), "tab\tand\nnewline");
  // Every Error message is printable, whatever the input held.
  const Error e(ErrorKind::input, "in\xfe.csv", 3, "id", "pole 'P\xff' is unknown");
  EXPECT_EQ(std::string(e.what()), "in\\xFE.csv:3: field 'id': pole 'P\\xFF' is unknown");
}

TEST(CsvTable, CrlfAndByteOrderMarkAreAccepted) {
  const CsvTable a = parse_csv("id,u,v\nP1,1.5,2\nP2,3,4\n", "a.csv");
  const CsvTable b = parse_csv("\xEF\xBB\xBFid,u,v\r\nP1,1.5,2\r\nP2,3,4\r\n", "b.csv");
  ASSERT_EQ(b.header, a.header);
  ASSERT_EQ(b.records.size(), 2u);
  EXPECT_EQ(b.column("id"), 0u);
  EXPECT_EQ(b.number(b.records[1], 2), 4.0);
  EXPECT_EQ(b.records[1].line, 3);
}

TEST(CsvTable, BytesThatAreNotUtf8AreRefusedWithLineAndColumn) {
  for (const auto& [text, line, column] : std::vector<std::tuple<std::string, long, std::string>>{
           {"id,u,v\nP1,1,2\nP\xff,3,4\n", 3, "column 2"},
           {"id,u\xc3,v\n", 1, "column 5"},
           {"id,u,v\r\n\r\nP1,1,2\r\nX,\x80,4\r\n", 4, "column 3"}}) {
    const Error e = csv_error(text);
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.line(), line);
    EXPECT_NE(std::string(e.what()).find(column), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not UTF-8"), std::string::npos) << e.what();
  }
}

TEST(CsvTable, NumberInRangeNamesTheRange) {
  const CsvTable t = parse_csv("E,N\n1,2\n70000,3\n", "p.csv");
  EXPECT_EQ(t.number_in(t.records[0], 0, -5e4, 5e4, "site ENU, m"), 1.0);
  try {
    t.number_in(t.records[1], 0, -5e4, 5e4, "site ENU, m");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "E");
    EXPECT_NE(std::string(e.what()).find("[-50000, 50000] (site ENU, m)"), std::string::npos) << e.what();
  }
}

TEST(JsonText, KeyGivenTwiceNamesTheKeyAndBothLines) {
  const Error top = json_error("{\n  \"a\": 1,\n  \"b\": 2,\n  \"a\": 3\n}\n");
  EXPECT_EQ(top.kind(), ErrorKind::usage);
  EXPECT_EQ(top.line(), 4);
  EXPECT_EQ(top.field(), "a");
  EXPECT_NE(std::string(top.what()).find("lines 2 and 4"), std::string::npos) << top.what();
  // Nested, and spelled with an escape.
  const Error nested = json_error("{\"cams\": [{\"id\": \"c1\",\n \"i\\u0064\": \"c2\"}]}");
  EXPECT_EQ(nested.line(), 2);
  EXPECT_EQ(nested.field(), "id");
  // The same key in different objects is fine, and so is a key equal to a string value.
  EXPECT_NO_THROW(parse_json_text("{\"a\": {\"x\": 1}, \"b\": {\"x\": 2}, \"c\": [\"a\", \"a\"]}", "ok.json",
                                  ErrorKind::usage));
}

TEST(JsonText, NumberBeyondADoubleNamesItsLineAndKeyPath) {
  struct Case {
    std::string text;
    long line;
    std::string field;  // the key path, spelled as JsonView's other errors spell it
  };
  for (const Case& c : std::vector<Case>{
           {"{\"x\": 1e999}", 1, "x"},
           {"{\n\"a\": [1,\n -2e400]\n}", 3, "a[1]"},
           {"[0.5,\n\n1E+309]", 3, "[1]"},
           {"{\"cameras\": [{\"id\": \"c1\"}, {\"id\": \"c2\", \"priors\": {\"w\": [[1, 2], [3]],\n"
            "\"center_enu_m\": [1, 2, 1e999]}}]}",
            2, "cameras[1].priors.center_enu_m[2]"},
           {"{\"a\": {\"b\": 1}, \"c\": 2, \"d\": -1e400}", 1, "d"}}) {
    const Error e = json_error(c.text);
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_EQ(e.line(), c.line) << c.text;
    EXPECT_EQ(e.field(), c.field) << c.text;
    EXPECT_NE(std::string(e.what()).find("beyond the range of a double"), std::string::npos) << e.what();
  }
}

// A ~200 KB file whose unknown key holds 100,000 nested arrays: refused before nlohmann parses it
// (its DOM copy and dump recurse per level), in one linear pass. The walk that names key paths
// used to build every open container's full path as it opened, quadratic in the depth: 109 s and
// 17.8 GB for this file.
TEST(JsonText, DeepNestingIsRefusedInLinearTimeNamingLineAndKeyPath) {
  const std::size_t depth = 100000;
  const std::string text = "{\n  \"mission\": \"deep\",\n  \"extra\": " + std::string(depth, '[') +
                           std::string(depth, ']') + "\n}\n";
  const auto t0 = std::chrono::steady_clock::now();
  const Error e = json_error(text);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(seconds, 0.5);
  EXPECT_EQ(e.kind(), ErrorKind::usage);
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.field().rfind("extra[0][0]", 0), 0u) << e.field();
  EXPECT_LT(e.field().size(), 60u) << "the key path of a deep value is shortened";
  EXPECT_NE(std::string(e.what()).find("nested deeper than " + std::to_string(kMaxJsonNesting) + " levels"),
            std::string::npos)
      << e.what();
  // Inside a string, brackets are text; the limit itself is accepted, one more level is not.
  EXPECT_NO_THROW(
      parse_json_text("{\"a\": \"" + std::string(depth, '[') + "\"}", "s.json", ErrorKind::usage));
  const auto nested = [](std::size_t levels) { return std::string(levels, '[') + std::string(levels, ']'); };
  EXPECT_NO_THROW(parse_json_text(nested(kMaxJsonNesting), "ok.json", ErrorKind::input));
  const Error over = json_error("{\"a\": [{\"b\": " + nested(kMaxJsonNesting - 2) + "}]}");
  EXPECT_EQ(over.field().rfind("a[0].b[0]", 0), 0u) << over.field();
  // The same walk names the key path of an overflowing number in a long array in linear time.
  std::string wide = "{\"w\": [";
  for (int i = 0; i < 200000; ++i) wide += "[1],";
  wide += "1e999]}";
  const auto t1 = std::chrono::steady_clock::now();
  const Error far = json_error(wide);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count(), 1.0);
  EXPECT_EQ(far.field(), "w[200000]");
}

TEST(JsonText, ByteOrderMarkIsAcceptedAndBadUtf8IsAnError) {
  EXPECT_EQ(parse_json_text("\xEF\xBB\xBF{\"a\": 1}", "bom.json", ErrorKind::usage)["a"], 1);
  const Error e = json_error("{\"id\": \"P\xff\"}");
  EXPECT_EQ(e.kind(), ErrorKind::usage);
  EXPECT_EQ(std::string(e.what()).find('\xff'), std::string::npos) << "raw byte in the message";
}

TEST(JsonFormat, InvalidUtf8InAStringDoesNotThrow) {
  nlohmann::ordered_json j;
  j["id"] = "P\xff";
  std::string out;
  EXPECT_NO_THROW(out = dump_json_compact_arrays(j));
  EXPECT_EQ(first_invalid_utf8(out), std::nullopt);
}

}  // namespace
}  // namespace rangecal
