// Photron .mraw reader/writer: the real samples' pixels against an independent decoding of their
// bytes written here, exact round trips of 8-, 12- and 16-bit files the writer makes, and bad
// .mraw files (missing header, size mismatch, frame index out of range) naming file and field.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <thread>

#include "config/error.hpp"
#include "support/expect_error.hpp"
#include "support/paths.hpp"
#include "vision/frames/frame_renderer.hpp"
#include "vision/frames/photron_mraw_reader.hpp"
#include "vision/frames/photron_mraw_writer.hpp"

using namespace rangecal;
namespace fs = std::filesystem;

namespace {

using test::expect_error;

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

std::vector<unsigned char> file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Independent decodings of the two layouts, straight from the format description (SOURCE.md):
// 16-bit little-endian words; 12-bit big-endian bit stream, pixel i at bit 12·i.
int pixel16(const std::vector<unsigned char>& b, std::size_t i) {
  return b[2 * i] + 256 * b[2 * i + 1];
}
int pixel12(const std::vector<unsigned char>& b, std::size_t i) {
  const std::size_t bit = 12 * i, byte = bit / 8;
  const int word = (b[byte] << 8) | b[byte + 1];  // the 12 bits lie within these two bytes
  return bit % 8 == 0 ? word >> 4 : word & 0xFFF;
}

void print_figures(const char* name, const cv::Mat& img) {
  double lo = 0, hi = 0;
  cv::minMaxLoc(img, &lo, &hi);
  std::printf("[ figures  ] %s: min %.0f max %.0f mean %.1f\n", name, lo, hi, cv::mean(img)[0]);
}

// `n` 16-bit frames with a lamp, values < 2^bits.
std::vector<cv::Mat> rendered(int n, int w, int h, int bits, int storage) {
  FrameRenderSettings st;
  st.width = w;
  st.height = h;
  st.bits = bits;
  st.sky_level = bits == 8 ? 40 : 300;
  st.read_noise = bits == 8 ? 2 : 6;
  std::vector<cv::Mat> out;
  for (int k = 0; k < n; ++k) {
    cv::Mat m = render_frame(st, {{10.3 + 5.1 * k, 8.6 + 2.2 * k, 1.3, bits == 8 ? 150.0 : 3000.0}}, 40 + k);
    if (storage != 8 && m.depth() == CV_8U) m.convertTo(m, CV_16U);
    out.push_back(m);
  }
  return out;
}

}  // namespace

TEST(PhotronMraw, RealBeamPixelsMatchAnIndependentDecoding) {
  const fs::path mraw = test::external("photron-mraw/beam.mraw");
  const PhotronMrawReader r(mraw.string());
  EXPECT_EQ(r.header().path, test::external("photron-mraw/beam.cihx").string());
  ASSERT_EQ(r.frame_count(), 4);
  EXPECT_EQ(r.bits(), 12);
  const auto bytes = file_bytes(mraw);
  ASSERT_EQ(bytes.size(), 655360u);
  const std::size_t n = 1024 * 80;
  std::vector<cv::Mat> frames;
  for (int k = 0; k < 4; ++k) {
    const ImageFrame f = r.read_frame(k);
    ASSERT_EQ(f.image.type(), CV_16UC1);
    ASSERT_EQ(f.image.cols, 1024);
    ASSERT_EQ(f.image.rows, 80);
    EXPECT_EQ(f.bits, 12);
    EXPECT_EQ(f.frame, k);
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < n; ++i)
      mismatches += f.image.at<std::uint16_t>(static_cast<int>(i / 1024), static_cast<int>(i % 1024)) !=
                    pixel16(bytes, k * n + i);
    EXPECT_EQ(mismatches, 0u) << "frame " << k;
    double hi = 0;
    cv::minMaxLoc(f.image, nullptr, &hi);
    EXPECT_LE(hi, 4095.0);  // 12 effective bits, lower side
    print_figures(("beam frame " + std::to_string(k)).c_str(), f.image);
    frames.push_back(f.image);
  }
  for (int k = 1; k < 4; ++k) {
    const int changed = cv::countNonZero(frames[k] != frames[0]);
    std::printf("[ figures  ] beam frame %d differs from frame 0 in %d of %zu pixels\n", k, changed, n);
    EXPECT_GT(changed, 0);
  }
}

TEST(PhotronMraw, RealBall12BitPixelsMatchAnIndependentDecoding) {
  const fs::path mraw = test::external("photron-mraw/ball_12bit.mraw");
  const PhotronMrawReader r(mraw.string());
  ASSERT_EQ(r.frame_count(), 15);
  EXPECT_EQ(r.bits(), 12);
  const auto bytes = file_bytes(mraw);
  ASSERT_EQ(bytes.size(), 3317760u);
  const std::size_t n = 384 * 384;
  for (int k : {0, 7, 14}) {
    const ImageFrame f = r.read_frame(k);
    ASSERT_EQ(f.image.type(), CV_16UC1);
    EXPECT_EQ(f.bits, 12);
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < n; ++i)
      mismatches += f.image.at<std::uint16_t>(static_cast<int>(i / 384), static_cast<int>(i % 384)) !=
                    pixel12(bytes, k * n + i);
    EXPECT_EQ(mismatches, 0u) << "frame " << k;
    print_figures(("ball frame " + std::to_string(k)).c_str(), f.image);
  }
  // Every frame within 12 bits; the ball moves, so frames differ.
  const cv::Mat first = r.read_frame(0).image, last = r.read_frame(14).image;
  for (int k = 0; k < 15; ++k) {
    double hi = 0;
    cv::minMaxLoc(r.read_frame(k).image, nullptr, &hi);
    EXPECT_LE(hi, 4095.0) << k;
  }
  const int changed = cv::countNonZero(first != last);
  std::printf("[ figures  ] ball frame 14 differs from frame 0 in %d of %zu pixels\n", changed, n);
  EXPECT_GT(changed, 100);
}

TEST(PhotronMraw, ConcurrentReadsAgree) {
  const PhotronMrawReader r(test::external("photron-mraw/ball_12bit.mraw").string());
  std::vector<cv::Mat> once;
  for (int k = 0; k < 15; ++k) once.push_back(r.read_frame(k).image);
  std::vector<int> bad(4, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int rep = 0; rep < 5; ++rep)
        for (int k = (t * 3) % 15, i = 0; i < 15; ++i, k = (k + 1) % 15)
          bad[t] += cv::norm(r.read_frame(k).image, once[k], cv::NORM_INF) != 0.0;
    });
  for (auto& th : threads) th.join();
  for (int t = 0; t < 4; ++t) EXPECT_EQ(bad[t], 0) << "thread " << t;
}

TEST(PhotronMraw, WrittenFilesRoundTripExactly) {
  const fs::path dir = test::scratch_dir("mraw_roundtrip");
  struct Case {
    int storage, depth;
    EffectiveBitSide side;
  };
  for (const Case& c : {Case{8, 8, EffectiveBitSide::lower}, Case{12, 12, EffectiveBitSide::lower},
                        Case{12, 10, EffectiveBitSide::higher}, Case{16, 16, EffectiveBitSide::lower},
                        Case{16, 12, EffectiveBitSide::lower}, Case{16, 12, EffectiveBitSide::higher}}) {
    const std::string name = "r" + std::to_string(c.storage) + "_" + std::to_string(c.depth) +
                             (c.side == EffectiveBitSide::higher ? "h" : "l");
    const auto frames = rendered(5, 48, 30, c.depth, c.storage);
    PhotronWriteOptions o;
    o.storage_bits = c.storage;
    o.effective_depth = c.depth;
    o.effective_side = c.side;
    o.record_rate_fps = 2000;
    const std::string mraw = (dir / (name + ".mraw")).string();
    EXPECT_EQ(write_photron_mraw(mraw, frames, o), (dir / (name + ".cihx")).string());
    EXPECT_EQ(fs::file_size(mraw), 5u * 48u * 30u * static_cast<unsigned>(c.storage) / 8u) << name;
    const PhotronMrawReader r(mraw);
    ASSERT_EQ(r.frame_count(), 5);
    EXPECT_EQ(r.header().color_bit, c.storage);
    EXPECT_EQ(r.bits(), c.depth);
    for (int k = 0; k < 5; ++k) {
      const ImageFrame f = r.read_frame(k);
      EXPECT_EQ(f.image.type(), c.storage == 8 ? CV_8UC1 : CV_16UC1) << name;
      EXPECT_EQ(f.bits, c.depth);
      EXPECT_EQ(cv::norm(f.image, frames[k], cv::NORM_INF), 0.0) << name << " frame " << k;
    }
  }
  // Higher side: the stored words carry the values in their top bits.
  const auto bytes = file_bytes(dir / "r16_12h.mraw");
  const cv::Mat f0 = rendered(1, 48, 30, 12, 16)[0];
  EXPECT_EQ(pixel16(bytes, 0), f0.at<std::uint16_t>(0, 0) << 4);

  // The writer refuses what the file could not hold.
  PhotronWriteOptions o;
  o.storage_bits = 12;
  auto e = expect_error([&] {
    write_photron_mraw((dir / "bad.mraw").string(), {cv::Mat(30, 48, CV_16UC1, cv::Scalar(5000))}, o);
  });
  EXPECT_TRUE(contains(e.what(), "does not fit 12 bits")) << e.what();
  e = expect_error([&] { write_photron_mraw((dir / "bad.mraw").string(), rendered(1, 7, 3, 12, 12), o); });
  EXPECT_TRUE(contains(e.what(), "even pixel count")) << e.what();
  o.storage_bits = 10;
  e = expect_error([&] { write_photron_mraw((dir / "bad.mraw").string(), rendered(1, 8, 4, 10, 16), o); });
  EXPECT_EQ(e.field(), "storage_bits");
}

TEST(PhotronMraw, BadRecordingsNameFileAndField) {
  const fs::path dir = test::scratch_dir("mraw_bad");
  const auto frames = rendered(4, 32, 16, 12, 16);
  PhotronWriteOptions o;
  o.storage_bits = 12;
  const std::string mraw = (dir / "rec.mraw").string();
  const std::string cihx = write_photron_mraw(mraw, frames, o);
  const std::string header_text = test::read_text(cihx);
  const PhotronMrawReader good(mraw);

  // Frame index beyond the end, or negative.
  for (std::int64_t k : {4ll, -1ll, 1ll << 40}) {
    const Error e = expect_error([&] { good.read_frame(k); });
    EXPECT_EQ(e.file(), mraw);
    EXPECT_EQ(e.field(), "frame");
    EXPECT_TRUE(contains(e.what(), "out of range") && contains(e.what(), "4 frames")) << e.what();
  }

  // .mraw shorter and longer than the header says: both sizes in the message.
  const std::string data = test::read_text(mraw);  // 4 × 32 × 16 × 1.5 = 3072 bytes
  test::write_text(mraw, data.substr(0, 3000));
  auto e = expect_error([&] { PhotronMrawReader r(mraw); });
  EXPECT_EQ(e.field(), "size");
  EXPECT_TRUE(contains(e.what(), "3000 bytes") && contains(e.what(), "= 3072 bytes") &&
              contains(e.what(), "rec.cihx"))
      << e.what();
  test::write_text(mraw, data + "x");
  e = expect_error([&] { PhotronMrawReader r(mraw); });
  EXPECT_TRUE(contains(e.what(), "3073 bytes")) << e.what();
  test::write_text(mraw, data);

  // Huge (but individually legal) header values: refused by the size check before any allocation.
  const auto edited = [&](const std::vector<std::pair<std::string, std::string>>& edits) {
    std::string t = header_text;
    for (const auto& [from, to] : edits)  // every occurrence (the resolution is written twice)
      for (std::size_t at = t.find(from); at != std::string::npos; at = t.find(from, at + to.size()))
        t.replace(at, from.size(), to);
    return t;
  };
  test::write_text(cihx, edited({{"<totalFrame>4</totalFrame>", "<totalFrame>1000000000</totalFrame>"}}));
  e = expect_error([&] { PhotronMrawReader r(mraw); });
  EXPECT_TRUE(contains(e.what(), "= 768000000000 bytes")) << e.what();
  test::write_text(cihx, edited({{"<width>32</width>", "<width>65534</width>"},
                                 {"<height>16</height>", "<height>65535</height>"},
                                 {"<totalFrame>4</totalFrame>", "<totalFrame>1000000000</totalFrame>"}}));
  e = expect_error([&] { PhotronMrawReader r(mraw); });
  EXPECT_EQ(e.field(), "size");
  EXPECT_TRUE(contains(e.what(), "65534x65535 px") && contains(e.what(), "3072 bytes")) << e.what();
  test::write_text(cihx, edited({{"<width>32</width>", "<width>100000</width>"},
                                 {"<height>16</height>", "<height>100000</height>"}}));
  e = expect_error([&] { PhotronMrawReader r(mraw); });
  EXPECT_EQ(e.field(), "imageDataInfo/resolution/width");
  EXPECT_TRUE(contains(e.what(), "100000 px")) << e.what();
  test::write_text(cihx, edited({{"<width>32</width>", "<width>0</width>"}}));
  e = expect_error([&] { PhotronMrawReader r(mraw); });
  EXPECT_EQ(e.field(), "imageDataInfo/resolution/width");
  test::write_text(cihx, edited({{"<bit>12</bit>", "<bit>10</bit>"}}));
  e = expect_error([&] { PhotronMrawReader r(mraw); });
  EXPECT_EQ(e.field(), "imageDataInfo/colorInfo/bit");
  test::write_text(cihx, edited({{"<type>Mono</type>", "<type>Color</type>"}}));
  e = expect_error([&] { PhotronMrawReader r(mraw); });
  EXPECT_EQ(e.field(), "imageDataInfo/colorInfo/type");
  EXPECT_TRUE(contains(e.what(), cihx)) << e.what();
  test::write_text(cihx, edited({{"<totalFrame>4</totalFrame>", ""}}));
  e = expect_error([&] { PhotronMrawReader r(mraw); });
  EXPECT_EQ(e.field(), "frameInfo/totalFrame");
  EXPECT_TRUE(contains(e.what(), "missing required field")) << e.what();
  test::write_text(cihx, edited({{"</frameInfo>", "</frameinfo>"}}));
  e = expect_error([&] { PhotronMrawReader r(mraw); });
  EXPECT_EQ(e.field(), "XML");
  EXPECT_TRUE(contains(e.what(), cihx)) << e.what();

  // No .mraw.
  test::write_text(cihx, header_text);
  e = expect_error([&] { PhotronMrawReader r((dir / "gone.mraw").string(), cihx); });
  EXPECT_TRUE(contains(e.what(), "gone.mraw") && contains(e.what(), "cannot open")) << e.what();
  // No header beside the .mraw.
  fs::remove(cihx);
  e = expect_error([&] { PhotronMrawReader r(mraw); });
  EXPECT_EQ(e.file(), mraw);
  EXPECT_EQ(e.field(), "header");
  EXPECT_TRUE(contains(e.what(), "rec.cihx")) << e.what();
}
