// rangecal's reader of OpenCV's YAML (config/opencv_yaml.hpp) against OpenCV itself: files written
// by cv::FileStorage are read to the same values as cv::FileStorage reads them (the independent
// reference, on well-formed files), and damaged files, including those on which OpenCV 4.6's own
// parser hangs or overflows its stack, end in an error naming the line and the key.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "config/error.hpp"
#include "config/opencv_yaml.hpp"
#include "support/expect_error.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

using Kind = OpenCvYamlEntry::Kind;

// Bitwise equality (denormals included); any NaN equals any NaN (OpenCV reads .Nan with the sign
// bit set).
bool same_bits(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0;
}

cv::Mat filled(int rows, int cols, int type, double scale) {
  cv::Mat m(rows, cols, type);
  const int n = rows * cols * m.channels();
  cv::Mat flat = m.reshape(1, 1);
  for (int i = 0; i < n; ++i) {
    const double v = scale * std::sin(1.7 * i + 0.3) * std::pow(10.0, (i % 7) - 3);
    switch (m.depth()) {
      case CV_8U:
        flat.at<std::uint8_t>(i) = static_cast<std::uint8_t>(i * 37 % 256);
        break;
      case CV_16S:
        flat.at<std::int16_t>(i) = static_cast<std::int16_t>(i * 911 % 65536 - 32768);
        break;
      case CV_32S:
        flat.at<std::int32_t>(i) = static_cast<std::int32_t>(v * 1e6);
        break;
      case CV_32F:
        flat.at<float>(i) = static_cast<float>(v);
        break;
      default:
        flat.at<double>(i) = v;
    }
  }
  return m;
}

// A file as OpenCV's calibration tools write one: scalars of every kind, matrices of several
// element types and sizes (long data lists wrap over lines), non-finite values, a list, a nested
// map and a list of maps.
std::string rich_file(std::vector<std::pair<std::string, cv::Mat>>* matrices) {
  matrices->clear();
  matrices->emplace_back("camera_matrix", filled(3, 3, CV_64F, 6000.0));
  matrices->emplace_back("distortion_coefficients", filled(1, 8, CV_64F, 1.0));
  matrices->emplace_back("extrinsic_parameters", filled(25, 6, CV_64F, 3.0));
  matrices->emplace_back("image_points", filled(54, 1, CV_32FC2, 900.0));
  matrices->emplace_back("mask", filled(7, 9, CV_8U, 1.0));
  matrices->emplace_back("labels", filled(4, 4, CV_32S, 1.0));
  matrices->emplace_back("offsets", filled(2, 5, CV_16S, 1.0));
  cv::Mat special =
      (cv::Mat_<double>(1, 6) << std::numeric_limits<double>::quiet_NaN(),
       std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), -0.0, 1.0, 5e-324);
  matrices->emplace_back("special", special);

  cv::FileStorage fs(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
  fs << "calibration_time"
     << "Wed Nov 25 05:12:00 2026";
  fs << "note"
     << "a # sign, \"quotes\", 'apostrophes', a back\\slash";
  fs << "count_as_text"
     << "123";
  fs << "nframes" << 25;
  fs << "image_width" << 1280;
  fs << "image_height" << 800;
  fs << "square_size" << 0.025;
  fs << "aspect_ratio" << 1.0;
  fs << "avg_reprojection_error" << 0.123456789012345678;
  fs << "flags" << -7;
  fs << "key with blanks" << 3;
  fs << "empty_matrix" << cv::Mat();
  for (const auto& [key, m] : *matrices) fs << key << m;
  fs << "view_counts" << std::vector<int>{54, 54, 48, 54, 50, 54, 54, 54, 54, 54, 54, 54, 54, 54, 54, 54};
  fs << "grid"
     << "{"
     << "rows" << 6 << "cols" << 9 << "pattern"
     << "chessboard"
     << "}";
  fs << "views"
     << "[";
  for (int i = 0; i < 3; ++i)
    fs << "{:"
       << "id" << i << "error" << 0.1 * i << "}";
  fs << "]";
  fs << "avg_after_lists" << 2.5;
  return fs.releaseAndGetString();
}

TEST(OpenCvYaml, ReadsWhatFileStorageWritesToTheValuesFileStorageReads) {
  std::vector<std::pair<std::string, cv::Mat>> matrices;
  const std::string text = rich_file(&matrices);
  const OpenCvYamlDocument doc = parse_opencv_yaml(text, "rich.yml");
  cv::FileStorage fs(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  ASSERT_TRUE(fs.isOpened());

  // Every top-level key, in file order, and no other.
  std::vector<std::string> keys;
  for (const auto& e : doc.entries) keys.push_back(e.key);
  std::vector<std::string> theirs;
  for (const cv::FileNode& n : fs.root()) theirs.push_back(n.name());
  EXPECT_EQ(keys, theirs);

  for (const char* key : {"nframes", "image_width", "image_height", "flags", "key with blanks"}) {
    const OpenCvYamlEntry* e = doc.find(key);
    ASSERT_NE(e, nullptr) << key;
    ASSERT_EQ(e->kind, Kind::scalar) << key;
    EXPECT_EQ(std::stol(e->scalar), static_cast<int>(fs[key])) << key;
  }
  for (const char* key : {"square_size", "aspect_ratio", "avg_reprojection_error", "avg_after_lists"}) {
    const OpenCvYamlEntry* e = doc.find(key);
    ASSERT_NE(e, nullptr) << key;
    double v = 0;
    ASSERT_TRUE(parse_opencv_yaml_real(e->scalar, &v)) << key << " '" << e->scalar << "'";
    EXPECT_TRUE(same_bits(v, static_cast<double>(fs[key]))) << key;
  }
  for (const char* key : {"calibration_time", "note", "count_as_text"}) {
    const OpenCvYamlEntry* e = doc.find(key);
    ASSERT_NE(e, nullptr) << key;
    EXPECT_EQ(e->scalar, static_cast<std::string>(fs[key])) << key;
  }
  for (const char* key : {"view_counts", "grid", "views"}) EXPECT_EQ(doc.find(key)->kind, Kind::other) << key;

  for (const auto& [key, written] : matrices) {
    const OpenCvYamlEntry* e = doc.find(key);
    ASSERT_NE(e, nullptr) << key;
    ASSERT_EQ(e->kind, Kind::matrix) << key;
    cv::Mat read;
    fs[key] >> read;
    EXPECT_EQ(e->rows, read.rows) << key;
    EXPECT_EQ(e->cols, read.cols) << key;
    EXPECT_EQ(e->channels, read.channels()) << key;
    EXPECT_EQ(e->depth, std::string("ucwsifdh")[static_cast<std::size_t>(read.depth())]) << key;
    cv::Mat as_double;
    read.reshape(1, 1).convertTo(as_double, CV_64F);
    ASSERT_EQ(e->data.size(), as_double.total()) << key;
    // The reader keeps the values as written (doubles); OpenCV stores a float matrix's as floats.
    for (std::size_t i = 0; i < e->data.size(); ++i) {
      const double mine = e->depth == 'f' ? static_cast<double>(static_cast<float>(e->data[i])) : e->data[i];
      ASSERT_TRUE(same_bits(mine, as_double.at<double>(static_cast<int>(i))))
          << key << "[" << i << "]: " << e->data[i] << " vs " << as_double.at<double>(static_cast<int>(i));
    }
    EXPECT_GT(e->data_line, e->line) << key;
  }
  const OpenCvYamlEntry* empty = doc.find("empty_matrix");
  EXPECT_EQ(empty->kind, Kind::matrix);
  EXPECT_EQ(empty->rows * empty->cols, 0);
  EXPECT_TRUE(empty->data.empty());
  // Every key's line, counted independently: lines are counted through the wrapped data lists,
  // the flow list, the nested map and the list of maps.
  for (const OpenCvYamlEntry& e : doc.entries) {
    const std::size_t at = text.find("\n" + e.key + ":");
    ASSERT_NE(at, std::string::npos) << e.key;
    EXPECT_EQ(e.line, 2 + std::count(text.begin(), text.begin() + static_cast<long>(at), '\n')) << e.key;
  }
}

TEST(OpenCvYaml, CrlfByteOrderMarkCommentsAndBlankLinesReadTheSame) {
  std::vector<std::pair<std::string, cv::Mat>> matrices;
  const std::string text = rich_file(&matrices);
  std::string windows = "\xEF\xBB\xBF# written on Windows\r\n";
  for (const char c : text) {
    if (c == '\n')
      windows += "\r\n";
    else
      windows.push_back(c);
  }
  windows += "\r\n# end\r\n\r\n";
  const OpenCvYamlDocument a = parse_opencv_yaml(text, "a.yml"), b = parse_opencv_yaml(windows, "b.yml");
  ASSERT_EQ(a.entries.size(), b.entries.size());
  for (std::size_t i = 0; i < a.entries.size(); ++i) {
    EXPECT_EQ(a.entries[i].key, b.entries[i].key);
    EXPECT_EQ(a.entries[i].scalar, b.entries[i].scalar);
    EXPECT_EQ(a.entries[i].data.size(), b.entries[i].data.size());
    EXPECT_EQ(a.entries[i].line + 1, b.entries[i].line);
  }
}

TEST(OpenCvYaml, RealsAsOpenCvWritesThem) {
  double v = 0;
  ASSERT_TRUE(parse_opencv_yaml_real("1.", &v));
  EXPECT_EQ(v, 1.0);
  ASSERT_TRUE(parse_opencv_yaml_real("-2.5000000000000000e-03", &v));
  EXPECT_EQ(v, -2.5e-3);
  ASSERT_TRUE(parse_opencv_yaml_real(".Nan", &v));
  EXPECT_TRUE(std::isnan(v));
  ASSERT_TRUE(parse_opencv_yaml_real("-.Inf", &v));
  EXPECT_EQ(v, -std::numeric_limits<double>::infinity());
  ASSERT_TRUE(parse_opencv_yaml_real(".INF", &v));
  EXPECT_EQ(v, std::numeric_limits<double>::infinity());
  for (const char* bad : {"", "x", "1.0.0", "1e999", "0x10", ".Nanx", "- 1"})
    EXPECT_FALSE(parse_opencv_yaml_real(bad, &v)) << bad;
}

// Nesting that OpenCV's parser follows by recursion (a stack overflow, docs/reliability.md) is
// skipped by counting brackets; a list of 200,000 values is read in one pass.
TEST(OpenCvYaml, DeepNestingAndLongListsAreReadWithoutRecursion) {
  const std::size_t depth = 200000;
  const std::string nested =
      "%YAML:1.0\n---\ndeep: " + std::string(depth, '[') + std::string(depth, ']') + "\nafter: 1\n";
  const OpenCvYamlDocument doc = parse_opencv_yaml(nested, "deep.yml");
  ASSERT_EQ(doc.entries.size(), 2u);
  EXPECT_EQ(doc.entries[0].kind, Kind::other);
  EXPECT_EQ(doc.find("after")->scalar, "1");
  EXPECT_EQ(doc.find("after")->line, 4);

  std::string big = "%YAML:1.0\n---\nm: !!opencv-matrix\n   rows: 1000\n   cols: 200\n   dt: d\n   data: [ ";
  for (int i = 0; i < 200000; ++i)
    big += std::to_string(i) + (i + 1 < 200000 ? (i % 4 == 3 ? ",\n      " : ", ") : " ]\n");
  const OpenCvYamlDocument m = parse_opencv_yaml(big, "big.yml");
  ASSERT_EQ(m.entries.at(0).data.size(), 200000u);
  EXPECT_EQ(m.entries[0].data.back(), 199999.0);

  // Memory stays bounded: a document of only keys stops at kOpenCvYamlMaxEntries.
  std::string keys = "%YAML:1.0\n---\n";
  for (std::size_t i = 0; i <= kOpenCvYamlMaxEntries; ++i) keys += "k" + std::to_string(i) + ": 1\n";
  const Error e = test::expect_error([&] { parse_opencv_yaml(keys, "keys.yml"); });
  EXPECT_EQ(e.line(), static_cast<long>(kOpenCvYamlMaxEntries) + 3);
  EXPECT_NE(std::string(e.what()).find("top-level keys"), std::string::npos) << e.what();
}

// Forms that people write by hand, or that other FileStorage modes produce.
TEST(OpenCvYaml, HandWrittenFormsReadAsCvFileStorageReadsThem) {
  const std::string text =
      "%YAML:1.0\n---\n"
      "K:\n   rows: 1\n   cols: 2\n   dt: d\n   data: [ 1.5, -2. ]\n"  // an untagged matrix
      "words: [ don't, \"x, y\" ]\n"                                   // an apostrophe in a word
      "escaped: \"tab\\there, \\\"quoted\\\"\"\n"
      "after: 7 # a comment\n";
  const OpenCvYamlDocument doc = parse_opencv_yaml(text, "hand.yml");
  cv::FileStorage fs(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  ASSERT_TRUE(fs.isOpened());
  const OpenCvYamlEntry* k = doc.find("K");
  ASSERT_EQ(k->kind, Kind::matrix);
  cv::Mat theirs;
  fs["K"] >> theirs;
  ASSERT_EQ(theirs.total(), 2u);
  EXPECT_EQ(k->data, (std::vector<double>{theirs.at<double>(0), theirs.at<double>(1)}));
  EXPECT_EQ(doc.find("words")->kind, Kind::other);
  EXPECT_EQ(doc.find("escaped")->scalar, "tab\there, \"quoted\"");
  EXPECT_EQ(doc.find("escaped")->scalar, static_cast<std::string>(fs["escaped"]));
  EXPECT_EQ(doc.find("after")->scalar, "7");
  EXPECT_EQ(doc.find("after")->line, 10);
  EXPECT_EQ(static_cast<int>(fs["after"]), 7);
  // YAML's compact list at column 0 and block scalars, which cv::FileStorage refuses ("Incorrect
  // indentation", "Multi-line text literals are not supported"), are skipped.
  const OpenCvYamlDocument yaml = parse_opencv_yaml(
      "list:\n- 1\n- 2\ntext: |\n   line one\n   line two\nafter: 3\nhex: \"\\x41\"\n", "yaml.yml");
  EXPECT_EQ(yaml.find("list")->kind, Kind::other);
  EXPECT_EQ(yaml.find("text")->kind, Kind::other);
  EXPECT_EQ(yaml.find("after")->line, 7);
  EXPECT_EQ(yaml.find("hex")->scalar, "A");
}

// FileStorage::APPEND adds a second document; the first is read, as cv::FileStorage's
// operator[] reads it.
TEST(OpenCvYaml, AppendedDocumentsAfterTheFirstAreNotRead) {
  const auto path = (test::scratch_dir("opencv_yaml_append") / "appended.yml").string();
  {
    cv::FileStorage w(path, cv::FileStorage::WRITE);
    w << "first" << 1;
  }
  {
    cv::FileStorage a(path, cv::FileStorage::APPEND);
    a << "second" << 2;
  }
  const OpenCvYamlDocument doc = read_opencv_yaml_file(path);
  cv::FileStorage fs(path, cv::FileStorage::READ);
  std::vector<std::string> theirs, mine;
  for (const cv::FileNode& n : fs.getFirstTopLevelNode()) theirs.push_back(n.name());
  for (const auto& e : doc.entries) mine.push_back(e.key);
  EXPECT_EQ(mine, theirs);
  EXPECT_EQ(mine, std::vector<std::string>{"first"}) << test::read_text(path);
}

struct Damaged {
  const char* name;
  std::string text;
  long line;
  const char* field;
  const char* reason;  // a part of the message
};

const std::string kMatrixHead = "%YAML:1.0\n---\nK: !!opencv-matrix\n   rows: 1\n   cols: 3\n   dt: d\n";

TEST(OpenCvYaml, DamagedFilesEndInAnErrorNamingLineAndKey) {
  const std::vector<Damaged> cases = {
      // OpenCV 4.6's FileStorage loops forever on these two (found by fuzz_opencv_camera_yml).
      {"hang_fuzz_reproducer", "%YAML:1.0\n---YAML:1.0\n\xE2---\nimage_wid7777\x04", 3, "",
       "byte 0xE2 at column 1 is not UTF-8"},
      {"hang_document_start", "%YAML:1.0\n---YAML:1.0\nx---\n", 2, "", "after the document start"},
      {"empty", "", 0, "", "empty"},
      {"only_comments", "%YAML:1.0\n---\n# nothing\n\n", 0, "", "empty"},
      {"xml", "<?xml version=\"1.0\"?>\n<opencv_storage>\n", 1, "", "XML"},
      {"json", "{\n  \"image_width\": 1280\n}\n", 1, "", "JSON"},
      {"yaml_2", "%YAML:2.0\n---\na: 1\n", 1, "", "unsupported directive"},
      {"top_level_list", "%YAML:1.0\n- 1\n- 2\n", 2, "", "list"},
      {"indented_first", "%YAML:1.0\n---\n   a: 1\n", 3, "", "indented"},
      {"not_a_key", "%YAML:1.0\n---\n1a: 2\n", 3, "", "a key starts with"},
      {"no_colon", "%YAML:1.0\n---\nimage_width 1280\n", 3, "image_width 1280", "expected ':'"},
      {"no_blank", "%YAML:1.0\n---\nimage_width:1280\n", 3, "image_width", "blank after"},
      {"twice", "%YAML:1.0\n---\na: 1\nb: 2\na: 3\n", 5, "a", "lines 3 and 5"},
      {"indented_after_scalar", "%YAML:1.0\n---\na: 1\n   b: 2\n", 4, "a", "indented line after"},
      {"open_quote", "%YAML:1.0\n---\na: \"text\n", 3, "a", "closing quote"},
      {"after_quote", "%YAML:1.0\n---\na: \"text\" more\n", 3, "a", "after the closing quote"},
      {"unclosed_flow", "%YAML:1.0\n---\na: [ 1, [ 2,\n   3 ]\nb: 1\n", 3, "a", "never closed"},
      {"after_flow", "%YAML:1.0\n---\na: [ 1, 2 ] x\n", 3, "a", "after the closing bracket"},
      {"control_byte", "%YAML:1.0\n---\na: 1\x01\n", 3, "", "control byte 0x01"},
      {"lone_cr", "%YAML:1.0\n---\na: 1\rb: 2\n", 3, "", "control byte 0x0D"},
      {"not_utf8", "%YAML:1.0\n---\na: \xFF\n", 3, "", "byte 0xFF at column 4 is not UTF-8"},
      {"matrix_no_data", kMatrixHead, 3, "K", "'data' is missing"},
      {"matrix_no_rows", "%YAML:1.0\n---\nK: !!opencv-matrix\n   cols: 3\n   dt: d\n   data: [ 1, 2, 3 ]\n",
       3, "K", "'rows' is missing"},
      {"matrix_count", kMatrixHead + "   data: [ 1., 2. ]\n", 7, "K", "data has 2 values"},
      {"matrix_huge_rows",
       "%YAML:1.0\n---\nK: !!opencv-matrix\n   rows: 999999999\n   cols: 3\n   dt: d\n   data: [ 1, 2, 3 ]\n",
       7, "K", "999999999 × 3 × 1"},
      {"matrix_rows_typo", "%YAML:1.0\n---\nK: !!opencv-matrix\n   rows:$3\n", 4, "K", "blank after 'rows:'"},
      {"matrix_rows_text", "%YAML:1.0\n---\nK: !!opencv-matrix\n   rows: three\n", 4, "K",
       "not a non-negative integer"},
      {"matrix_rows_negative", "%YAML:1.0\n---\nK: !!opencv-matrix\n   rows: -1\n", 4, "K",
       "not a non-negative integer"},
      {"matrix_base64", kMatrixHead + "   data: !!binary |\n      AAAA\n", 7, "K", "base64"},
      {"indented_after_matrix", kMatrixHead + "   data: [ 1., 2., 3. ]\nb: 1\n   c: 2\n", 9, "b",
       "indented line after"},
      {"indented_after_flow", "%YAML:1.0\n---\na: [ 1 ]\n   c: 2\n", 4, "a", "indented line"},
      {"key_too_long", "%YAML:1.0\n---\n" + std::string(300, 'k') + ": 1\n", 3, "", "more than 256"},
      {"first_bad_byte_first", "%YAML:1.0\n---\na: \xFF\nb: \x01\n", 3, "", "not UTF-8"},
      {"matrix_dt", "%YAML:1.0\n---\nK: !!opencv-matrix\n   dt: q\n", 4, "K", "not an OpenCV element type"},
      {"matrix_dt_channels", "%YAML:1.0\n---\nK: !!opencv-matrix\n   dt: 999d\n", 4, "K",
       "not an OpenCV element type"},
      {"matrix_subkey", "%YAML:1.0\n---\nK: !!opencv-matrix\n   step: 3\n", 4, "K", "unexpected key 'step'"},
      {"matrix_subkey_twice", "%YAML:1.0\n---\nK: !!opencv-matrix\n   rows: 1\n   rows: 1\n", 5, "K",
       "twice"},
      {"matrix_empty_value", kMatrixHead + "   data: [ 1., , 3. ]\n", 7, "K", "empty value"},
      {"matrix_trailing_comma", kMatrixHead + "   data: [ 1., 2., 3., ]\n", 7, "K", "empty value"},
      {"matrix_no_comma", kMatrixHead + "   data: [ 1. 2., 3. ]\n", 7, "K", "expected ','"},
      {"matrix_not_number", kMatrixHead + "   data: [ 1.,\n      2.,\n      x ]\n", 9, "K",
       "'x' is not a number"},
      {"matrix_nested", kMatrixHead + "   data: [ [ 1. ] ]\n", 7, "K", "nested list"},
      {"matrix_unclosed", kMatrixHead + "   data: [ 1., 2., 3.\n", 7, "K", "never closed"},
      {"matrix_not_list", kMatrixHead + "   data: 1.\n", 7, "K", "expected a list"},
      {"matrix_after_list", kMatrixHead + "   data: [ 1., 2., 3. ] 4.\n", 7, "K",
       "after the closing bracket"},
  };
  for (const Damaged& c : cases) {
    SCOPED_TRACE(c.name);
    const Error e = test::expect_error([&] { parse_opencv_yaml(c.text, std::string(c.name) + ".yml"); });
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), std::string(c.name) + ".yml");
    EXPECT_EQ(e.line(), c.line) << e.what();
    EXPECT_EQ(e.field(), c.field) << e.what();
    EXPECT_NE(std::string(e.what()).find(c.reason), std::string::npos) << e.what();
  }
}

TEST(OpenCvYaml, FileReaderNamesMissingAndOversizedFiles) {
  const auto dir = test::scratch_dir("opencv_yaml_files");
  const std::string missing = (dir / "nope.yml").string();
  Error e = test::expect_error([&] { read_opencv_yaml_file(missing); });
  EXPECT_EQ(e.file(), missing);
  EXPECT_EQ(e.exit_code(), 3);
  e = test::expect_error([&] { read_opencv_yaml_file(dir.string()); });
  EXPECT_EQ(e.file(), dir.string());
  const std::string big = (dir / "big.yml").string();
  {
    std::string text = "%YAML:1.0\n---\n# padding\n";
    text.resize(kOpenCvYamlMaxBytes + 1, '#');
    test::write_text(big, text);
  }
  e = test::expect_error([&] { read_opencv_yaml_file(big); });
  EXPECT_EQ(e.file(), big);
  EXPECT_NE(std::string(e.what()).find("MiB"), std::string::npos) << e.what();
  std::filesystem::remove(big);
}

}  // namespace
}  // namespace rangecal
