// Frame sources: timestamps CSV over PNG/TIFF (8/16-bit, colour), a video and a .cine; a .cine
// alone; the same centroids from every format; bad input with file, line and field.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "config/error.hpp"
#include "support/paths.hpp"
#include "vision/detection/lamp_detector.hpp"
#include "vision/frames/cine_writer.hpp"
#include "vision/frames/frame_renderer.hpp"
#include "vision/frames/frame_source.hpp"

using namespace rangecal;
namespace fs = std::filesystem;

namespace {

constexpr int kW = 320, kH = 200;
const UtcTime kT0 = *parse_iso8601_utc("2026-05-01T08:00:00Z");

std::string iso(int k) {
  return format_iso8601_utc(UtcTime{kT0.ns + k * 100'000'000ll}, 9);
}

FrameSourceOptions sensor(int w = kW, int h = kH, bool allow_missing = false) {
  FrameSourceOptions s;
  s.width_px = w;
  s.height_px = h;
  s.allow_missing = allow_missing;
  return s;
}

// Frames with a moving lamp (8-bit values, so every format can hold them exactly).
std::vector<cv::Mat> lamp_frames(int n) {
  FrameRenderSettings st;
  st.width = kW;
  st.height = kH;
  st.bits = 8;
  st.read_noise = 2.0;
  std::vector<cv::Mat> out;
  for (int k = 0; k < n; ++k)
    out.push_back(render_frame(st, {{60.3 + 21.7 * k, 40.6 + 13.1 * k, 1.3, 90}}, 100 + k));
  return out;
}

std::string expect_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no rangecal::Error thrown";
  return "";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST(FrameSource, ImagesOfEveryDepthAndColour) {
  const fs::path dir = test::scratch_dir("fs_images");
  const auto frames = lamp_frames(4);
  cv::Mat f16;
  frames[1].convertTo(f16, CV_16U, 256.0);
  cv::Mat colour;
  cv::cvtColor(frames[3], colour, cv::COLOR_GRAY2BGR);
  write_frame_image((dir / "img/a.png").string(), frames[0]);
  write_frame_image((dir / "img/b.png").string(), f16);
  write_frame_image((dir / "img/c.tif").string(), frames[2]);
  write_frame_image((dir / "img/d.tiff").string(), colour);
  test::write_text(dir / "ts.csv", "frame,file,utc\n0,img/a.png," + iso(0) + "\n2,img/b.png," + iso(2) +
                                       "\n5,img/c.tif," + iso(5) + "\n9,img/d.tiff," + iso(9) + "\n");
  const FrameSource src = FrameSource::from_timestamps_csv((dir / "ts.csv").string(), sensor());
  ASSERT_EQ(src.size(), 4u);
  const auto a = src.load(0), b = src.load(1), c = src.load(2), d = src.load(3);
  EXPECT_EQ(a->bits, 8);
  EXPECT_EQ(b->bits, 16);
  EXPECT_EQ(b->image.type(), CV_16UC1);
  EXPECT_EQ(cv::norm(a->image, frames[0], cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(b->image, f16, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(c->image, frames[2], cv::NORM_INF), 0.0);
  EXPECT_EQ(d->image.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(d->image, frames[3], cv::NORM_INF), 0.0);  // grey → BGR → grey is exact
  EXPECT_EQ(c->frame, 5);
  EXPECT_EQ(c->utc.ns, kT0.ns + 500'000'000);
}

// Acceptance: 16-bit and 8-bit frames, PNG and TIFF, a video file and a .cine give the same
// centroids for the same content.
TEST(FrameSource, SameCentroidsFromEveryFormat) {
  const fs::path dir = test::scratch_dir("fs_formats");
  const int n = 6;
  const auto frames = lamp_frames(n);
  std::vector<cv::Mat> frames16;
  for (const auto& f : frames) {
    cv::Mat m;
    f.convertTo(m, CV_16U);
    frames16.push_back(m);
  }
  std::vector<UtcTime> times;
  for (int k = 0; k < n; ++k) times.push_back(UtcTime{kT0.ns + k * 100'000'000ll});
  std::map<std::string, std::string> csv;
  for (const std::string kind : {"png8", "tif8", "png16", "tif16"}) {
    std::string text = "frame,file,utc\n";
    for (int k = 0; k < n; ++k) {
      const std::string name = kind + "_" + std::to_string(k) + (kind.rfind("png", 0) == 0 ? ".png" : ".tif");
      write_frame_image((dir / name).string(), kind.back() == '8' ? frames[k] : frames16[k]);
      text += std::to_string(k) + "," + name + "," + iso(k) + "\n";
    }
    csv[kind] = text;
  }
  // Lossless video (FFV1 in AVI, available in Debian's OpenCV/FFmpeg).
  {
    cv::VideoWriter vw((dir / "v.avi").string(), cv::CAP_FFMPEG, cv::VideoWriter::fourcc('F', 'F', 'V', '1'),
                       10, cv::Size(kW, kH), false);
    ASSERT_TRUE(vw.isOpened());
    for (const auto& f : frames) vw.write(f);
  }
  CineWriteOptions o8;
  o8.storage_bits = 8;
  write_cine((dir / "c8.cine").string(), frames, times, o8);
  CineWriteOptions o16;
  o16.storage_bits = 16;
  write_cine((dir / "c16.cine").string(), frames16, times, o16);
  for (const std::string kind : {"v.avi", "c8.cine", "c16.cine"}) {
    std::string text = "frame,file,utc\n";
    for (int k = 0; k < n; ++k) text += std::to_string(k) + "," + kind + "," + iso(k) + "\n";
    csv[kind] = text;
  }

  LampDetectorOptions opt;
  std::vector<std::size_t> idx(n);
  std::iota(idx.begin(), idx.end(), 0);
  std::vector<LampDetection> ref;
  for (const auto& [kind, text] : csv) {
    test::write_text(dir / (kind + ".csv"), text);
    const FrameSource src = FrameSource::from_timestamps_csv((dir / (kind + ".csv")).string(), sensor());
    const auto det = detect_lamp(src, idx, opt, 2);
    ASSERT_EQ(det.size(), static_cast<std::size_t>(n));
    if (ref.empty()) ref = det;
    for (int k = 0; k < n; ++k) {
      EXPECT_TRUE(det[k].usable()) << kind << " frame " << k << " " << det[k].status;
      EXPECT_NEAR(det[k].u, ref[k].u, 1e-9) << kind << " frame " << k;
      EXPECT_NEAR(det[k].v, ref[k].v, 1e-9) << kind << " frame " << k;
      EXPECT_EQ(det[k].utc, ref[k].utc);
      EXPECT_NEAR(det[k].u, 60.3 + 21.7 * k, 0.1);  // and they are right
      EXPECT_NEAR(det[k].v, 40.6 + 13.1 * k, 0.1);
    }
  }
  // A .cine alone brings its own time stamps.
  const FrameSource alone = FrameSource::from_cine((dir / "c16.cine").string(), sensor());
  ASSERT_EQ(alone.size(), static_cast<std::size_t>(n));
  EXPECT_EQ(alone.entry(3).utc, times[3]);
  const auto det = detect_lamp(alone, idx, opt, 1);
  for (int k = 0; k < n; ++k) EXPECT_NEAR(det[k].u, ref[k].u, 1e-9);
  // Only the requested frames are decoded, in the order asked.
  const auto some = detect_lamp(alone, {4, 1}, opt, 2);
  ASSERT_EQ(some.size(), 2u);
  EXPECT_EQ(some[0].frame, 4);
  EXPECT_NEAR(some[1].u, ref[1].u, 1e-9);
}

TEST(FrameSource, BadTimestampsCsv) {
  const fs::path dir = test::scratch_dir("fs_bad_csv");
  write_frame_image((dir / "a.png").string(), lamp_frames(1)[0]);
  test::write_text(dir / "order.csv", "frame,file,utc\n0,a.png," + iso(1) + "\n1,a.png," + iso(0) + "\n");
  auto m = expect_error([&] { FrameSource::from_timestamps_csv((dir / "order.csv").string(), sensor()); });
  EXPECT_TRUE(contains(m, "order.csv:3")) << m;
  EXPECT_TRUE(contains(m, "utc")) << m;
  test::write_text(dir / "parse.csv", "frame,file,utc\n0,a.png,2026-05-01 08:00:00\n");
  m = expect_error([&] { FrameSource::from_timestamps_csv((dir / "parse.csv").string(), sensor()); });
  EXPECT_TRUE(contains(m, "parse.csv:2")) << m;
  EXPECT_TRUE(contains(m, "utc")) << m;
  test::write_text(dir / "frame.csv", "frame,file,utc\n3,a.png," + iso(0) + "\n3,a.png," + iso(1) + "\n");
  m = expect_error([&] { FrameSource::from_timestamps_csv((dir / "frame.csv").string(), sensor()); });
  EXPECT_TRUE(contains(m, "frame.csv:3")) << m;
  test::write_text(dir / "col.csv", "frame,path,utc\n0,a.png," + iso(0) + "\n");
  m = expect_error([&] { FrameSource::from_timestamps_csv((dir / "col.csv").string(), sensor()); });
  EXPECT_TRUE(contains(m, "file")) << m;
  test::write_text(dir / "ext.csv", "frame,file,utc\n0,a.jpg," + iso(0) + "\n");
  m = expect_error([&] { FrameSource::from_timestamps_csv((dir / "ext.csv").string(), sensor()); });
  EXPECT_TRUE(contains(m, "ext.csv:2")) << m;
}

TEST(FrameSource, MissingUnreadableAndWrongSizeFrames) {
  const fs::path dir = test::scratch_dir("fs_bad_frames");
  const auto frames = lamp_frames(2);
  write_frame_image((dir / "a.png").string(), frames[0]);
  test::write_text(dir / "broken.png", "this is not a png");
  cv::Mat small;
  cv::resize(frames[1], small, cv::Size(kW / 2, kH / 2));
  write_frame_image((dir / "small.tif").string(), small);
  test::write_text(dir / "ts.csv", "frame,file,utc\n0,a.png," + iso(0) + "\n1,gone.png," + iso(1) +
                                       "\n2,broken.png," + iso(2) + "\n3,small.tif," + iso(3) + "\n");
  const std::string csv = (dir / "ts.csv").string();
  const FrameSource strict = FrameSource::from_timestamps_csv(csv, sensor());
  EXPECT_TRUE(strict.load(0).has_value());
  auto m = expect_error([&] { strict.load(1); });
  EXPECT_TRUE(contains(m, "ts.csv:3") && contains(m, "gone.png") && contains(m, "missing")) << m;
  m = expect_error([&] { strict.load(2); });
  EXPECT_TRUE(contains(m, "ts.csv:4") && contains(m, "broken.png") && contains(m, "decode")) << m;
  m = expect_error([&] { strict.load(3); });
  EXPECT_TRUE(contains(m, "ts.csv:5") && contains(m, "160x100") && contains(m, "320x200")) << m;

  // Allowed: missing/unreadable frames are skipped and reported; a wrong size is still an error.
  const FrameSource lenient = FrameSource::from_timestamps_csv(csv, sensor(kW, kH, true));
  std::string why;
  EXPECT_FALSE(lenient.load(1, &why).has_value());
  EXPECT_TRUE(contains(why, "gone.png")) << why;
  EXPECT_FALSE(lenient.load(2, &why).has_value());
  EXPECT_TRUE(contains(why, "broken.png")) << why;
  EXPECT_THROW(lenient.load(3), Error);
  const auto det = detect_lamp(lenient, {0, 1, 2}, LampDetectorOptions{}, 2);
  EXPECT_TRUE(det[0].usable());
  EXPECT_EQ(det[1].status, lamp_status::kMissingFrame);
  EXPECT_EQ(det[2].status, lamp_status::kMissingFrame);
  // Strict detection fails on the first bad frame in order, naming it.
  m = expect_error([&] { detect_lamp(strict, {0, 2, 1}, LampDetectorOptions{}, 2); });
  EXPECT_TRUE(contains(m, "ts.csv:4")) << m;
}

TEST(FrameSource, ContainersOutOfRangeOrMissing) {
  const fs::path dir = test::scratch_dir("fs_bad_containers");
  const auto frames = lamp_frames(2);
  CineWriteOptions o8;
  o8.storage_bits = 8;
  write_cine((dir / "c.cine").string(), frames, {kT0, UtcTime{kT0.ns + 1000}}, o8);
  test::write_text(dir / "beyond.csv", "frame,file,utc\n0,c.cine," + iso(0) + "\n7,c.cine," + iso(1) + "\n");
  auto m = expect_error([&] { FrameSource::from_timestamps_csv((dir / "beyond.csv").string(), sensor()); });
  EXPECT_TRUE(contains(m, "beyond.csv:3") && contains(m, "frame")) << m;
  test::write_text(dir / "nofile.csv", "frame,file,utc\n0,none.avi," + iso(0) + "\n");
  m = expect_error([&] { FrameSource::from_timestamps_csv((dir / "nofile.csv").string(), sensor()); });
  EXPECT_TRUE(contains(m, "nofile.csv:2") && contains(m, "none.avi")) << m;
  // Wrong sensor size for a .cine alone.
  const FrameSource alone = FrameSource::from_cine((dir / "c.cine").string(), sensor(640, 480));
  m = expect_error([&] { alone.load(0); });
  EXPECT_TRUE(contains(m, "c.cine") && contains(m, "640x480")) << m;
}

// A frame's size is read from its header before it is decoded (PNG IHDR, TIFF first IFD), so a
// timestamps CSV naming a forged 30,000-pixel image is refused at once instead of costing a
// multi-gigabyte decode for each of its rows.
TEST(FrameSource, FrameSizeIsCheckedFromTheHeaderBeforeDecoding) {
  const fs::path dir = test::scratch_dir("fs_header_size");
  const auto frames = lamp_frames(1);
  write_frame_image((dir / "a.png").string(), frames[0]);
  write_frame_image((dir / "a.tif").string(), frames[0]);
  for (const char* name : {"a.png", "a.tif"}) {
    const std::string text = test::read_text(dir / name);
    const std::optional<cv::Size> size =
        image_header_size(std::vector<unsigned char>(text.begin(), text.end()));
    ASSERT_TRUE(size.has_value()) << name;
    EXPECT_EQ(size->width, kW) << name;
    EXPECT_EQ(size->height, kH) << name;
  }
  // The same PNG with IHDR saying 30000 x 30000 (bytes 16-23, big-endian).
  std::string forged = test::read_text(dir / "a.png");
  for (int k : {16, 20}) {
    forged[k] = 0, forged[k + 1] = 0, forged[k + 2] = char(0x75), forged[k + 3] = char(0x30);
  }
  test::write_text(dir / "huge.png", forged);
  std::string csv = "frame,file,utc\n";
  for (int k = 0; k < 1000; ++k) csv += std::to_string(k) + ",huge.png," + iso(k) + "\n";
  test::write_text(dir / "ts.csv", csv);
  const FrameSource lenient =
      FrameSource::from_timestamps_csv((dir / "ts.csv").string(), sensor(kW, kH, true));
  for (std::size_t i : {0u, 999u}) {
    const std::string m = expect_error([&] { lenient.load(i); });
    EXPECT_TRUE(contains(m, "ts.csv:" + std::to_string(i + 2)) &&
                contains(m, "30000x30000 px by its header") && contains(m, "320x200"))
        << m;
  }
}
