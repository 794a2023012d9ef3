// Phantom .cine reader/writer: the real sample's header values (external/phantom-cine/SOURCE.md),
// its single frame, TIME64 conversion, and exact round trips of files the writer makes.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <limits>

#include "config/error.hpp"
#include "support/expect_error.hpp"
#include "support/paths.hpp"
#include "vision/frames/cine_format.hpp"
#include "vision/frames/cine_reader.hpp"
#include "vision/frames/cine_writer.hpp"
#include "vision/frames/frame_renderer.hpp"

using namespace rangecal;
namespace fs = std::filesystem;

TEST(Cine, RealSampleHeaderMatchesSourceMd) {
  const CineReader r(test::external("phantom-cine/chart1.cine").string());
  const CineHeader& h = r.header();
  EXPECT_EQ(h.header_size, 44);
  // SOURCE.md says "compression 0"; the file's CINEFILEHEADER.Compression field (bytes 4–5) is 2
  // (uninterpolated CFA data), consistent with SETUP.CFA = 3 (Bayer) — we assert the file.
  EXPECT_EQ(h.compression, 2);
  EXPECT_EQ(h.version, 1);
  EXPECT_EQ(h.first_movie_image, -175);
  EXPECT_EQ(h.total_image_count, 176u);
  EXPECT_EQ(h.first_image_no, -123);
  EXPECT_EQ(h.image_count, 1u);
  EXPECT_EQ(h.off_image_header, 0x2Cu);
  EXPECT_EQ(h.off_setup, 0x54u);
  EXPECT_EQ(h.off_image_offsets, 0x2910u);
  EXPECT_EQ(h.width(), 2048);
  EXPECT_EQ(h.height(), 1080);
  EXPECT_EQ(h.bi_bit_count, 16);
  EXPECT_EQ(h.bi_compression, 256u);  // Phantom packed 10-bit
  EXPECT_EQ(h.bi_size_image, 2048u * 1080u * 10u / 8u);
  EXPECT_EQ(h.setup_length, 10384);
  EXPECT_EQ(h.frame_rate, 25u);
  EXPECT_EQ(h.real_bpp, 10u);
  EXPECT_EQ(h.cfa, 3u);
  EXPECT_EQ(r.frame_count(), 1u);
  EXPECT_EQ(r.bits(), 10);
  // TIME64 values decoded independently from the raw bytes (python: seconds 0x396D9C0C,
  // fraction 0x528C7B93 → 963484684 s + 322456096 ns; trigger 1405334289 s + 274831000 ns).
  ASSERT_TRUE(r.has_times());
  EXPECT_EQ(format_iso8601_utc(r.frame_time(0)), "2000-07-13T10:38:04.322456096Z");
  EXPECT_TRUE(r.frame_irig_locked(0));
  EXPECT_EQ(format_iso8601_utc(h.trigger_time), "2014-07-14T10:38:09.274831000Z");
  ASSERT_TRUE(r.exposure_s(0).has_value());
  EXPECT_NEAR(*r.exposure_s(0), 0.0200018, 1e-6);
  EXPECT_EQ(h.shutter_ns, 20000078u);
}

TEST(Cine, RealSampleFrameDecodesPlausibly) {
  const CineReader r(test::external("phantom-cine/chart1.cine").string());
  const cv::Mat img = r.read_image(0);
  ASSERT_EQ(img.type(), CV_16UC1);
  ASSERT_EQ(img.cols, 2048);
  ASSERT_EQ(img.rows, 1080);
  double lo = 0, hi = 0;
  cv::minMaxLoc(img, &lo, &hi);
  cv::Scalar mean, sd;
  cv::meanStdDev(img, mean, sd);
  EXPECT_LT(hi, 1024);   // 10-bit codes
  EXPECT_GT(hi, 200);    // a lit chart, not an empty frame
  EXPECT_GT(sd[0], 10);  // structure, not a constant
  EXPECT_GT(mean[0], 20);
  EXPECT_LT(mean[0], 1000);
  // A test chart: neighbouring rows are far more alike than rows far apart (a wrong unpacking
  // or row stride scrambles this).
  const double near = cv::norm(img.row(500), img.row(501), cv::NORM_L1);
  const double far = cv::norm(img.row(100), img.row(900), cv::NORM_L1);
  EXPECT_LT(near, 0.5 * far);
  EXPECT_THROW(r.read_image(1), Error);
}

TEST(Cine, Time64Conversion) {
  // 1.5 s: fraction 0x80000000; lowest bit is the IRIG flag, not time.
  const auto t = cine::time64_to_utc((1ull << 32) | 0x80000000ull);
  EXPECT_EQ(t.utc.ns, 1'500'000'000);
  EXPECT_FALSE(t.irig_locked);
  const auto t2 = cine::time64_to_utc((1ull << 32) | 0x80000001ull);
  EXPECT_EQ(t2.utc.ns, 1'500'000'000);
  EXPECT_TRUE(t2.irig_locked);
  RenderRandom rng(7);
  for (int i = 0; i < 100000; ++i) {
    const UtcTime u{1'700'000'000'000'000'000ll + static_cast<std::int64_t>(rng.next() % 100'000'000'000ull)};
    const bool irig = (i & 1) != 0;
    const auto back = cine::time64_to_utc(cine::utc_to_time64(u, irig));
    ASSERT_EQ(back.utc.ns, u.ns);
    ASSERT_EQ(back.irig_locked, irig);
  }
}

namespace {
void round_trip(int storage_bits, int w, int h) {
  const fs::path dir = test::scratch_dir("cine_rt_" + std::to_string(storage_bits));
  const std::string path = (dir / "rt.cine").string();
  RenderRandom rng(42 + storage_bits);
  std::vector<cv::Mat> images;
  std::vector<UtcTime> times;
  const int max_value = (1 << storage_bits) - 1;
  for (int k = 0; k < 3; ++k) {
    cv::Mat m(h, w, storage_bits == 8 ? CV_8UC1 : CV_16UC1);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int val = static_cast<int>(rng.next() % static_cast<std::uint64_t>(max_value + 1));
        if (storage_bits == 8)
          m.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(val);
        else
          m.at<std::uint16_t>(y, x) = static_cast<std::uint16_t>(val);
      }
    images.push_back(m);
    times.push_back(UtcTime{1'763'900'000'123'456'789ll + k * 1'000'037ll});
  }
  CineWriteOptions o;
  o.storage_bits = storage_bits;
  o.frame_rate = 1000;
  o.exposure_s = 0.0005;
  o.first_image_no = -5;
  o.trigger_time = times[1];
  write_cine(path, images, times, o);
  const CineReader r(path);
  ASSERT_EQ(r.frame_count(), 3u);
  EXPECT_EQ(r.header().width(), w);
  EXPECT_EQ(r.header().height(), h);
  EXPECT_EQ(r.header().first_image_no, -5);
  EXPECT_EQ(r.header().frame_rate, 1000u);
  EXPECT_EQ(r.bits(), storage_bits);
  EXPECT_EQ(r.header().trigger_time, times[1]);
  for (int k = 0; k < 3; ++k) {
    const cv::Mat back = r.read_image(static_cast<std::size_t>(k));
    ASSERT_EQ(back.type(), images[k].type());
    EXPECT_EQ(cv::norm(back, images[k], cv::NORM_INF), 0.0) << "image " << k << " storage " << storage_bits;
    EXPECT_EQ(r.frame_time(static_cast<std::size_t>(k)).ns, times[k].ns);
    EXPECT_TRUE(r.frame_irig_locked(static_cast<std::size_t>(k)));
    EXPECT_NEAR(*r.exposure_s(static_cast<std::size_t>(k)), 0.0005, 1e-9);
  }
}
}  // namespace

TEST(Cine, RoundTrip8Bit) {
  round_trip(8, 64, 37);
}
TEST(Cine, RoundTrip16Bit) {
  round_trip(16, 64, 37);
}
TEST(Cine, RoundTripPacked10Bit) {
  round_trip(10, 64, 37);
}
TEST(Cine, RoundTripPacked12Bit) {
  round_trip(12, 66, 37);
}

TEST(Cine, BadFiles) {
  const fs::path dir = test::scratch_dir("cine_bad");
  // Missing.
  try {
    CineReader r((dir / "none.cine").string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("none.cine"), std::string::npos);
  }
  // Not a cine.
  test::write_text(dir / "text.cine", std::string(200, 'x'));
  try {
    CineReader r((dir / "text.cine").string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("CI"), std::string::npos) << e.what();
  }
  // Truncated: a valid file cut inside the pixels of its last image.
  std::vector<cv::Mat> imgs(2, cv::Mat(16, 16, CV_16UC1, cv::Scalar(7)));
  CineWriteOptions o;
  write_cine((dir / "ok.cine").string(), imgs, {UtcTime{1'000'000'000}, UtcTime{2'000'000'000}}, o);
  const std::string bytes = test::read_text(dir / "ok.cine");
  test::write_text(dir / "cut.cine", bytes.substr(0, bytes.size() - 100));
  const CineReader cut((dir / "cut.cine").string());
  EXPECT_NO_THROW(cut.read_image(0));
  try {
    cut.read_image(1);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("image 1"), std::string::npos) << e.what();
  }
  // Writer refuses times out of order and values that do not fit the packing.
  EXPECT_THROW(write_cine((dir / "x.cine").string(), imgs, {UtcTime{2}, UtcTime{1}}, o), Error);
  o.storage_bits = 10;
  std::vector<cv::Mat> big(1, cv::Mat(4, 4, CV_16UC1, cv::Scalar(1024)));
  EXPECT_THROW(write_cine((dir / "y.cine").string(), big, {UtcTime{1}}, o), Error);
}

// Header values that would overflow or mislead the decoder are refused with the header field.
TEST(Cine, ImpossibleBitmapHeaderValues) {
  const fs::path dir = test::scratch_dir("cine_bad_header");
  std::vector<cv::Mat> imgs(1, cv::Mat(16, 16, CV_16UC1, cv::Scalar(7)));
  write_cine((dir / "ok.cine").string(), imgs, {UtcTime{1'000'000'000}}, CineWriteOptions{});
  const std::string ok = test::read_text(dir / "ok.cine");
  std::uint32_t off_image_header = 0;
  std::memcpy(&off_image_header, ok.data() + 24, 4);  // CINEFILEHEADER.OffImageHeader
  auto patched = [&](std::size_t at, const void* value, std::size_t n) {
    std::string b = ok;
    std::memcpy(&b[off_image_header + at], value, n);
    return b;
  };
  const std::int32_t int32_min = std::numeric_limits<std::int32_t>::min(), huge = 100000, zero = 0;
  const std::uint16_t seven = 7, twelve = 12;
  struct Case {
    std::string name, bytes, field;
  };
  const std::vector<Case> cases = {{"height_int32_min", patched(8, &int32_min, 4), "biHeight"},
                                   {"height_huge", patched(8, &huge, 4), "biHeight"},
                                   {"height_zero", patched(8, &zero, 4), "biHeight"},
                                   {"width_huge", patched(4, &huge, 4), "biWidth"},
                                   {"bit_count_7", patched(14, &seven, 2), "biBitCount"},
                                   {"bit_count_12", patched(14, &twelve, 2), "biBitCount"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path path = dir / (c.name + ".cine");
    test::write_text(path, c.bytes);
    const Error e = test::expect_error([&] { CineReader r(path.string()); });
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), path.string());
    EXPECT_NE(e.field().find(c.field), std::string::npos) << e.what();
  }
}

// biSizeImage is one image's bytes: a header claiming fewer than width × height × bytes per pixel
// (here the real sample's 2048 × 1080 packed 10-bit: 2,764,800 bytes) is refused naming the file
// and the field, on a damaged copy (the original is never edited).
TEST(Cine, BitmapSizeImageSmallerThanTheImageIsRefused) {
  const fs::path dir = test::scratch_dir("cine_bad_size_image");
  const std::string ok = test::read_text(test::external("phantom-cine/chart1.cine"));
  std::uint32_t off_image_header = 0;
  std::memcpy(&off_image_header, ok.data() + 24, 4);  // CINEFILEHEADER.OffImageHeader
  std::uint32_t recorded = 0;
  std::memcpy(&recorded, ok.data() + off_image_header + 20, 4);  // BITMAPINFOHEADER.biSizeImage
  ASSERT_EQ(recorded, 2048u * 1080u * 10u / 8u);
  for (const std::uint32_t value : {0u, 1u, 2048u * 1080u, 2048u * 1080u * 10u / 8u - 1u}) {
    SCOPED_TRACE(value);
    std::string b = ok;
    std::memcpy(&b[off_image_header + 20], &value, 4);
    const fs::path path = dir / ("size_image_" + std::to_string(value) + ".cine");
    test::write_text(path, b);
    const Error e = test::expect_error([&] { CineReader r(path.string()); });
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), path.string());
    EXPECT_EQ(e.field(), "BITMAPINFOHEADER.biSizeImage") << e.what();
    EXPECT_NE(std::string(e.what()).find("2764800 bytes"), std::string::npos) << e.what();
  }
  // One byte more than needed is a valid header (Phantom may pad); the exact size is the sample.
  std::string b = ok;
  const std::uint32_t more = recorded + 1;
  std::memcpy(&b[off_image_header + 20], &more, 4);
  test::write_text(dir / "padded.cine", b);
  EXPECT_NO_THROW(CineReader((dir / "padded.cine").string()));
}
