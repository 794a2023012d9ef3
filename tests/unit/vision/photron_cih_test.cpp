// Photron headers (.cihx XML and .cih text): the real samples' values (external/photron-mraw/
// SOURCE.md), the strict XML reader, every bad-header class naming file and field, the header
// clock, and robustness: truncated and corrupted copies of a real header throw rangecal::Error and
// nothing else.
#include <gtest/gtest.h>

#include <functional>

#include "config/error.hpp"
#include "config/xml_tree.hpp"
#include "support/expect_error.hpp"
#include "support/paths.hpp"
#include "vision/frames/frame_renderer.hpp"
#include "vision/frames/photron_cih.hpp"

using namespace rangecal;
namespace fs = std::filesystem;

namespace {

const std::string kBeam = test::external("photron-mraw/beam.cihx").string();
const std::string kBall = test::external("photron-mraw/ball_12bit.cihx").string();

using test::expect_error;

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// A minimal valid .cihx document with `fields` inside <cih>.
std::string cihx(const std::string& fields) {
  return "preamble\r\n<?xml version=\"1.0\" encoding=\"utf-8\"?>\r\n<cih>\r\n" + fields + "</cih>\r\n";
}
const std::string kFields =
    "<fileInfo><date>2026/5/1</date><time>10:00:00</time></fileInfo>\n"
    "<imageFileInfo><fileFormat>MRaw</fileFormat></imageFileInfo>\n"
    "<imageDataInfo><resolution><width>64</width><height>32</height></resolution>\n"
    "<colorInfo><type>Mono</type><bit>16</bit></colorInfo>\n"
    "<effectiveBit><depth>12</depth><side>Lower</side></effectiveBit></imageDataInfo>\n"
    "<frameInfo><totalFrame>3</totalFrame><startFrame>0</startFrame><skipFrame>1</skipFrame></frameInfo>\n"
    "<recordInfo><recordRate>1000</recordRate></recordInfo>\n";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const std::size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

PhotronHeader parse_x(const std::string& text) {
  return parse_photron_header(text, "t.cihx", PhotronHeaderFormat::cihx);
}

// Expects an input error about `t.cihx`, field `field`, whose message contains `words`.
void expect_cihx_error(const std::string& text, const std::string& field, const std::string& words) {
  const Error e = expect_error([&] { parse_x(text); });
  EXPECT_EQ(e.kind(), ErrorKind::input);
  EXPECT_EQ(e.file(), "t.cihx");
  EXPECT_EQ(e.field(), field) << e.what();
  EXPECT_TRUE(contains(e.what(), words)) << e.what();
}

}  // namespace

TEST(PhotronCih, RealBeamHeaderMatchesSourceMd) {
  const PhotronHeader h = read_photron_header(kBeam);
  EXPECT_EQ(h.format, PhotronHeaderFormat::cihx);
  EXPECT_EQ(h.width, 1024);
  EXPECT_EQ(h.height, 80);
  EXPECT_EQ(h.color_type, "Mono");
  EXPECT_EQ(h.color_bit, 16);
  EXPECT_EQ(h.effective_depth, 12);
  EXPECT_EQ(h.effective_side, EffectiveBitSide::lower);
  EXPECT_EQ(h.total_frame, 4);
  ASSERT_TRUE(h.record_rate_fps.has_value());
  EXPECT_EQ(*h.record_rate_fps, 50000.0);
  ASSERT_TRUE(h.irig.has_value());
  EXPECT_FALSE(*h.irig);
  EXPECT_EQ(h.irig_phase_lock, std::optional<bool>(false));
  // The rest as the file writes them.
  EXPECT_EQ(h.start_frame, std::optional<std::int64_t>(0));
  EXPECT_EQ(h.recorded_frame, std::optional<std::int64_t>(400));
  EXPECT_EQ(h.correct_trigger_frame, std::optional<std::int64_t>(0));
  EXPECT_EQ(h.skip_frame, std::optional<std::int64_t>(2500));
  ASSERT_TRUE(h.shutter_s.has_value());
  EXPECT_NEAR(*h.shutter_s, 5e-6, 1e-15);  // shutterSpeedNsec 5000 (shutterSpeed 1/200000)
  EXPECT_EQ(h.date, "2017/7/13");
  EXPECT_EQ(h.time, "13:13");
  EXPECT_EQ(h.trigger_time, "0");
  EXPECT_EQ(h.device_name, "FASTCAM SA-Z type 2100K-M-64GB");
  EXPECT_EQ(h.frame_bytes(), 1024u * 80u * 2u);
  // Its time has no seconds: no frame clock from this header.
  const Error e = expect_error([&] { photron_frame_clock(h, 0.0); });
  EXPECT_EQ(e.field(), "fileInfo/time");
  EXPECT_TRUE(contains(e.what(), "no seconds") && contains(e.what(), "timestamps")) << e.what();
}

TEST(PhotronCih, RealBall12BitHeaderMatchesSourceMd) {
  const PhotronHeader h = read_photron_header(kBall);
  EXPECT_EQ(h.width, 384);
  EXPECT_EQ(h.height, 384);
  EXPECT_EQ(h.color_bit, 12);
  EXPECT_EQ(h.effective_depth, 12);
  EXPECT_EQ(h.total_frame, 15);
  EXPECT_EQ(*h.record_rate_fps, 30000.0);
  EXPECT_EQ(h.date, "2023/1/18");
  EXPECT_EQ(h.time, "11:56:13");
  EXPECT_EQ(h.irig, std::optional<bool>(false));
  // SOURCE.md does not say it: the colour type is "Raw" from a monochrome model (1100K-M), which
  // the reader accepts as grey.
  EXPECT_EQ(h.color_type, "Raw");
  EXPECT_EQ(h.device_name, "FASTCAM Nova S16 type 1100K-M-64GB 10GbE model");
  EXPECT_EQ(h.start_frame, std::optional<std::int64_t>(52));
  EXPECT_EQ(h.skip_frame, std::optional<std::int64_t>(1));
  EXPECT_EQ(h.recorded_frame, std::optional<std::int64_t>(2000));
  EXPECT_FALSE(h.correct_trigger_frame.has_value());  // not in this file
  EXPECT_NEAR(*h.shutter_s, 20e-6, 1e-15);
  EXPECT_EQ(h.frame_bytes(), 384u * 384u * 3u / 2u);
  // Header clock: 11:56:13 on a clock 1 h ahead of UTC; saved frame k is camera frame 52 + k at
  // 30,000 fps after the trigger.
  const PhotronFrameClock c = photron_frame_clock(h, 1.0);
  EXPECT_EQ(format_iso8601_utc(c.trigger_utc), "2023-01-18T10:56:13.000000000Z");
  EXPECT_EQ(format_iso8601_utc(c.frame_time(0)), "2023-01-18T10:56:13.001733333Z");   // 52/30000 s
  EXPECT_EQ(format_iso8601_utc(c.frame_time(1)), "2023-01-18T10:56:13.001766667Z");   // 53/30000 s
  EXPECT_EQ(format_iso8601_utc(c.frame_time(14)), "2023-01-18T10:56:13.002200000Z");  // 66/30000 s
  EXPECT_EQ(format_iso8601_utc(photron_frame_clock(h, -5.5).trigger_utc), "2023-01-18T17:26:13.000000000Z");
}

TEST(PhotronCih, OldCihTextHeader) {
  const fs::path dir = test::scratch_dir("cih_text");
  const std::string text =
      "#Camera Information Header\n"
      "Date : 2016/4/21\nTime : 00:11:05\nCamera Type : FASTCAM SA-Z type 2100K-M-64GB\n"
      "Record Rate(fps) : 60000\nShutter Speed(s) : 1/800000\nTrigger Mode : Start\n"
      "Original Total Frame : 677\nTotal Frame : 12\nStart Frame : 49300\nCorrect Trigger Frame : 1\n"
      "Save Step : 36\nImage Width : 896\nImage Height : 368\nColor Type : Mono\nColor Bit : 16\n"
      "File Format : MRaw\nEffectiveBit Depth : 12\nEffectiveBit Side : Higher\n"
      "Partition Number: 1\nDevice Last Error : -1:0xffffffff\nNot Use : \nNot Use : \nIRIG : Off\n"
      "\n#Photron Fastcam Viewer Version Information:\nSaved Date : 2016/6/13\nEND\n"
      "#after END\nTotal Frame : 99\nno colon here\n";
  test::write_text(dir / "rec.cih", text);
  const PhotronHeader h = read_photron_header((dir / "rec.cih").string());
  EXPECT_EQ(h.format, PhotronHeaderFormat::cih);
  EXPECT_EQ(h.width, 896);
  EXPECT_EQ(h.height, 368);
  EXPECT_EQ(h.total_frame, 12);  // lines after END are not header fields
  EXPECT_EQ(h.effective_side, EffectiveBitSide::higher);
  EXPECT_EQ(h.skip_frame, std::optional<std::int64_t>(36));
  EXPECT_EQ(h.start_frame, std::optional<std::int64_t>(49300));
  EXPECT_NEAR(*h.shutter_s, 1.25e-6, 1e-18);
  EXPECT_EQ(h.irig, std::optional<bool>(false));
  EXPECT_EQ(h.time, "00:11:05");
  const PhotronFrameClock c = photron_frame_clock(h, 0.0);
  // 49300 + 36 k frames at 60 kfps after 00:11:05.
  EXPECT_EQ(format_iso8601_utc(c.frame_time(1)), "2016-04-21T00:11:05.822266667Z");

  // Bad .cih: a missing field, a line that is not Key : Value, a field given twice, a binary file.
  auto e = expect_error([&] {
    parse_photron_header(replaced(text, "Total Frame : 12\n", ""), "r.cih", PhotronHeaderFormat::cih);
  });
  EXPECT_EQ(e.field(), "Total Frame");
  EXPECT_TRUE(contains(e.what(), "r.cih") && contains(e.what(), "missing required field")) << e.what();
  e = expect_error([&] {
    parse_photron_header(replaced(text, "Trigger Mode : Start", "Trigger Mode Start"), "r.cih",
                         PhotronHeaderFormat::cih);
  });
  EXPECT_EQ(e.line(), 7);
  EXPECT_TRUE(contains(e.what(), "Key : Value")) << e.what();
  e = expect_error([&] {
    parse_photron_header(replaced(text, "Color Bit : 16\n", "Color Bit : 16\nColor Bit : 8\n"), "r.cih",
                         PhotronHeaderFormat::cih);
  });
  EXPECT_EQ(e.field(), "Color Bit");
  EXPECT_TRUE(contains(e.what(), "2 times")) << e.what();
  e = expect_error([&] {
    parse_photron_header(std::string("Image Width : 8\n\x01\x02\x03", 19), "r.cih", PhotronHeaderFormat::cih);
  });
  EXPECT_TRUE(contains(e.what(), "control byte") && !contains(e.what(), "\x01")) << e.what();
  e = expect_error([&] { parse_photron_header("", "r.cih", PhotronHeaderFormat::cih); });
  EXPECT_TRUE(contains(e.what(), "empty")) << e.what();
}

TEST(PhotronCih, StrictXml) {
  // Well-formed extras are fine: comments, attributes, entities, CDATA, self-closing elements, and
  // whatever follows the root (PFV appends a binary block).
  const std::string ok = cihx(
      "<!-- a comment --><basicInfo version='2' a=\"&lt;&amp;&gt;\"><comment><![CDATA[x<y]]> "
      "&#65;&#x42;</comment>"
      "<empty/></basicInfo>" +
      kFields);
  const XmlElement root =
      parse_xml_document(ok + std::string("\x02\x00\x78\xff", 4), ok.find("<?xml"), "t.cihx");
  EXPECT_EQ(root.name, "cih");
  const auto basic = root.children_named("basicInfo");
  ASSERT_EQ(basic.size(), 1u);
  EXPECT_EQ(basic[0]->attributes.at(1).second, "<&>");
  EXPECT_EQ(basic[0]->children_named("comment")[0]->text, "x<y AB");
  EXPECT_EQ(parse_x(ok).width, 64);

  // Malformed documents: each an input error with the file, the line and field 'XML'.
  struct Case {
    std::string text, words;
    long line;
  };
  const std::vector<Case> cases = {
      {replaced(cihx(kFields), "</width>", "</widht>"), "does not match", 6},
      {cihx(kFields).substr(0, cihx(kFields).size() / 2), "not closed", 0},
      {replaced(cihx(kFields), "<height>32", "<height>3\x01"), "control byte 0x01", 6},
      {replaced(cihx(kFields), "Mono", "M&ono;"), "undefined entity", 7},
      {replaced(cihx(kFields), "Mono", "M&#0;o"), "character", 7},
      {replaced(cihx(kFields), "<cih>", "<!DOCTYPE cih><cih>"), "DOCTYPE", 3},
      {replaced(cihx(kFields), "<fileInfo>", "<fileInfo a=1>"), "quoted value", 4},
      {replaced(cihx(kFields), "<fileInfo>", "<fileInfo a='1' a='2'>"), "twice", 4},
      {replaced(cihx(kFields), "<fileInfo>", "<fileInfo\xC3\xA9>"), "whitespace", 4},
      {replaced(cihx(kFields), "<fileInfo>", "<1fileInfo>"), "name", 4},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Error e = expect_error([&] { parse_x(cases[i].text); });
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "t.cihx");
    EXPECT_EQ(e.field(), "XML") << e.what();
    if (cases[i].line > 0) {
      EXPECT_EQ(e.line(), cases[i].line) << e.what();
    }
    EXPECT_TRUE(contains(e.what(), cases[i].words)) << i << ": " << e.what();
    for (char c : std::string(e.what()))
      EXPECT_TRUE(static_cast<unsigned char>(c) >= 0x20) << "raw byte in message " << i;
  }
  // Unclosed comment, a document that is not <cih>, no document at all, nesting 100 deep.
  auto e = expect_error([&] { parse_x(replaced(cihx(kFields), "<fileInfo>", "<!-- open <fileInfo>")); });
  EXPECT_TRUE(contains(e.what(), "comment is not closed")) << e.what();
  expect_cihx_error("<?xml version='1.0'?><cjh></cjh>", "cih", "not <cih>");
  expect_cihx_error(std::string(300, '\0') + "CIHX binary only", "cih", "no XML document");
  std::string deep;
  for (int i = 0; i < 100; ++i) deep += "<a>";
  e = expect_error([&] { parse_x(cihx(deep)); });
  EXPECT_TRUE(contains(e.what(), "deeper than 64")) << e.what();
  std::string many;
  for (int i = 0; i < 100001; ++i) many += "<a/>";
  e = expect_error([&] { parse_x(cihx(many)); });
  EXPECT_TRUE(contains(e.what(), "more than 100000 elements")) << e.what();
  // A field given twice is ambiguous.
  expect_cihx_error(cihx(kFields + "<frameInfo><totalFrame>9</totalFrame></frameInfo>"),
                    "frameInfo/totalFrame", "2 times");
}

TEST(PhotronCih, MissingAndBadFieldsNameTheField) {
  const std::string good = cihx(kFields);
  EXPECT_EQ(parse_x(good).total_frame, 3);
  // Every required field, removed in turn.
  const std::vector<std::pair<std::string, std::string>> required = {
      {"<width>64</width>", "imageDataInfo/resolution/width"},
      {"<height>32</height>", "imageDataInfo/resolution/height"},
      {"<type>Mono</type>", "imageDataInfo/colorInfo/type"},
      {"<bit>16</bit>", "imageDataInfo/colorInfo/bit"},
      {"<depth>12</depth>", "imageDataInfo/effectiveBit/depth"},
      {"<side>Lower</side>", "imageDataInfo/effectiveBit/side"},
      {"<fileFormat>MRaw</fileFormat>", "imageFileInfo/fileFormat"},
      {"<totalFrame>3</totalFrame>", "frameInfo/totalFrame"},
  };
  for (const auto& [element, field] : required)
    expect_cihx_error(replaced(good, element, ""), field, "missing");
  expect_cihx_error(replaced(good, "<totalFrame>3</totalFrame>", "<totalFrame> </totalFrame>"),
                    "frameInfo/totalFrame", "missing required field");
  // Unsupported or impossible values.
  expect_cihx_error(replaced(good, "<bit>16</bit>", "<bit>10</bit>"), "imageDataInfo/colorInfo/bit",
                    "unsupported stored bit depth 10");
  expect_cihx_error(replaced(good, "<width>64</width>", "<width>0</width>"), "imageDataInfo/resolution/width",
                    "0 px");
  expect_cihx_error(replaced(good, "<width>64</width>", "<width>100000</width>"),
                    "imageDataInfo/resolution/width", "100000 px");
  expect_cihx_error(replaced(good, "<height>32</height>", "<height>-5</height>"),
                    "imageDataInfo/resolution/height", "-5 px");
  expect_cihx_error(replaced(good, "<width>64</width>", "<width>99999999999999999999</width>"),
                    "imageDataInfo/resolution/width", "expected an integer");
  expect_cihx_error(replaced(good, "<width>64</width>",
                             "<width>6\xC3\xA9"
                             "4</width>"),
                    "imageDataInfo/resolution/width", "'6??4'");
  expect_cihx_error(replaced(good, "<width>64</width>", "<width><px>64</px></width>"),
                    "imageDataInfo/resolution/width", "single value");
  expect_cihx_error(replaced(good, "<type>Mono</type>", "<type>Color</type>"), "imageDataInfo/colorInfo/type",
                    "colour recording");
  expect_cihx_error(replaced(good, "<type>Mono</type>", "<type>Raw</type>"), "imageDataInfo/colorInfo/type",
                    "cannot tell grey from a colour mosaic");
  {
    const std::string raw_colour = replaced(
        replaced(good, "<type>Mono</type>", "<type>Raw</type>"), "<recordInfo>",
        "<deviceInfo><deviceName>FASTCAM Nova S16 type 1100K-C-64GB</deviceName></deviceInfo><recordInfo>");
    expect_cihx_error(raw_colour, "imageDataInfo/colorInfo/type", "Raw data from a colour camera");
  }
  expect_cihx_error(replaced(good, "<type>Mono</type>", "<type>Spectral</type>"),
                    "imageDataInfo/colorInfo/type", "unknown colour type");
  expect_cihx_error(replaced(good, "<depth>12</depth>", "<depth>17</depth>"),
                    "imageDataInfo/effectiveBit/depth", "does not fit");
  expect_cihx_error(replaced(good, "<depth>12</depth>", "<depth>6</depth>"),
                    "imageDataInfo/effectiveBit/depth", "6 bits");
  expect_cihx_error(replaced(good, "<side>Lower</side>", "<side>Middle</side>"),
                    "imageDataInfo/effectiveBit/side", "Lower or Higher");
  expect_cihx_error(replaced(good, "<fileFormat>MRaw</fileFormat>", "<fileFormat>Tiff</fileFormat>"),
                    "imageFileInfo/fileFormat", "only MRaw");
  expect_cihx_error(replaced(good, "<totalFrame>3</totalFrame>", "<totalFrame>0</totalFrame>"),
                    "frameInfo/totalFrame", "expected 1");
  expect_cihx_error(replaced(replaced(replaced(good, "<bit>16</bit>", "<bit>12</bit>"), "<width>64</width>",
                                      "<width>63</width>"),
                             "<height>32</height>", "<height>33</height>"),
                    "imageDataInfo/colorInfo/bit", "even pixel count");
  expect_cihx_error(replaced(good, "<recordRate>1000</recordRate>", "<recordRate>fast</recordRate>"),
                    "recordInfo/recordRate", "expected a number");
  expect_cihx_error(replaced(good, "<recordInfo>", "<deviceInfo><irig>maybe</irig></deviceInfo><recordInfo>"),
                    "deviceInfo/irig", "0/1");
}

TEST(PhotronCih, HeaderClockRequiresUsableFields) {
  const std::string good = cihx(kFields);
  const PhotronFrameClock c = photron_frame_clock(parse_x(good), 2.0);
  EXPECT_EQ(format_iso8601_utc(c.frame_time(2)), "2026-05-01T08:00:00.002000000Z");
  struct Case {
    std::string text, field, words;
  };
  const std::vector<Case> cases = {
      {replaced(good, "<date>2026/5/1</date>", ""), "fileInfo/date", "missing"},
      {replaced(good, "<date>2026/5/1</date>", "<date>1 May 2026</date>"), "fileInfo/date", "not a date"},
      {replaced(good, "<date>2026/5/1</date>", "<date>2026/2/30</date>"), "fileInfo/date", "not a date"},
      {replaced(good, "<date>2026/5/1</date>", "<date>3020/2/29</date>"), "fileInfo/date", "1970-2200"},
      {replaced(good, "<time>10:00:00</time>", ""), "fileInfo/time", "missing"},
      {replaced(good, "<time>10:00:00</time>", "<time>10:00</time>"), "fileInfo/time", "no seconds"},
      {replaced(good, "<time>10:00:00</time>", "<time>25:00:00</time>"), "fileInfo/time", "not a time"},
      {replaced(good, "<recordRate>1000</recordRate>", ""), "recordInfo/recordRate", "missing"},
      {replaced(good, "<recordRate>1000</recordRate>", "<recordRate>0</recordRate>"), "recordInfo/recordRate",
       "frame rate"},
      {replaced(good, "<startFrame>0</startFrame>", ""), "frameInfo/startFrame", "missing"},
      {replaced(good, "<skipFrame>1</skipFrame>", ""), "frameInfo/skipFrame", "missing"},
      {replaced(good, "<skipFrame>1</skipFrame>", "<skipFrame>0</skipFrame>"), "frameInfo/skipFrame",
       "save step"},
  };
  for (const Case& k : cases) {
    const PhotronHeader h = parse_x(k.text);  // the pixels do not need these fields
    const Error e = expect_error([&] { photron_frame_clock(h, 0.0); });
    EXPECT_EQ(e.file(), "t.cihx");
    EXPECT_EQ(e.field(), k.field) << e.what();
    EXPECT_TRUE(contains(e.what(), k.words) && contains(e.what(), "frames.timestamps")) << e.what();
  }
  const Error e = expect_error([&] { photron_frame_clock(parse_x(good), 15.0); });
  EXPECT_TRUE(contains(e.what(), "14 h")) << e.what();
}

TEST(PhotronCih, MissingOrWrongHeaderFile) {
  const fs::path dir = test::scratch_dir("cih_files");
  auto e = expect_error([&] { read_photron_header((dir / "none.cihx").string()); });
  EXPECT_TRUE(contains(e.what(), "none.cihx") && contains(e.what(), "missing")) << e.what();
  test::write_text(dir / "big.cihx", std::string((1u << 20) + 1, ' '));
  e = expect_error([&] { read_photron_header((dir / "big.cihx").string()); });
  EXPECT_TRUE(contains(e.what(), "too large")) << e.what();
  e = expect_error([&] { read_photron_header((dir / "x.txt").string()); });
  EXPECT_TRUE(contains(e.what(), ".cihx or .cih")) << e.what();
  e = expect_error([&] { find_photron_header((dir / "rec.mraw").string()); });
  EXPECT_EQ(e.field(), "header");
  EXPECT_TRUE(contains(e.what(), "rec.mraw") && contains(e.what(), "rec.cihx") &&
              contains(e.what(), "rec.cih"))
      << e.what();
  // .cihx is preferred when both exist; .cih alone is found.
  test::write_text(dir / "rec.cih", "x");
  EXPECT_EQ(find_photron_header((dir / "rec.mraw").string()), (dir / "rec.cih").string());
  test::write_text(dir / "rec.cihx", "x");
  EXPECT_EQ(find_photron_header((dir / "rec.mraw").string()), (dir / "rec.cihx").string());
}

// Robustness: every truncation of the real header (in steps of 37 bytes) and 2000 copies with
// random bytes overwritten either parse or throw rangecal::Error — never another exception or a
// crash (the run under AddressSanitizer is the stronger form of this test).
TEST(PhotronCih, TruncatedAndCorruptedRealHeaderThrowOnlyRangecalErrors) {
  const std::string bytes = test::read_text(kBeam);
  int parsed = 0, refused = 0;
  const auto attempt = [&](const std::string& b) {
    try {
      parse_photron_header(b, "beam.cihx", PhotronHeaderFormat::cihx);
      ++parsed;
    } catch (const Error& e) {
      ++refused;
      EXPECT_EQ(e.kind(), ErrorKind::input);
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not a rangecal::Error: " << e.what();
    }
  };
  for (std::size_t n = 0; n < bytes.size(); n += 37) attempt(bytes.substr(0, n));
  RenderRandom rng(7);
  for (int i = 0; i < 2000; ++i) {
    std::string b = bytes;
    const int hits = 1 + static_cast<int>(rng.next() % 4);
    for (int k = 0; k < hits; ++k) b[rng.next() % b.size()] = static_cast<char>(rng.next() & 0xFF);
    attempt(b);
  }
  std::printf("[ figures  ] corrupted beam.cihx: %d parsed, %d refused with rangecal::Error\n", parsed,
              refused);
  EXPECT_GT(refused, 300);
  EXPECT_GT(parsed, 100);  // most single-byte hits land in the LUT tables and change nothing we read
}
