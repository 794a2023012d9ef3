// detections.csv: fixed formatting, round trip, and bad-input messages.
#include <gtest/gtest.h>

#include "config/error.hpp"
#include "support/paths.hpp"
#include "vision/detection/detections_csv.hpp"

using namespace rangecal;

namespace {
std::vector<LampDetection> sample_rows() {
  LampDetection a;
  a.frame = 12;
  a.utc = *parse_iso8601_utc("2026-05-01T08:00:00.123456789Z");
  a.u = 640.123456;
  a.v = 399.5;
  a.peak = 123.45;
  a.area = 17;
  a.snr = 41.156;
  a.status = lamp_status::kOk;
  LampDetection b;
  b.frame = 14;
  b.utc = *parse_iso8601_utc("2026-05-01T08:00:00.2Z");
  b.status = lamp_status::kNoLamp;
  return {a, b};
}
}  // namespace

TEST(DetectionsIo, FormatIsFixed) {
  EXPECT_EQ(format_detections_csv(sample_rows()),
            "frame,utc,u,v,peak,area,snr,status\n"
            "12,2026-05-01T08:00:00.123456789Z,640.1235,399.5000,123.5,17,41.16,ok\n"
            "14,2026-05-01T08:00:00.200000000Z,,,,,,no_lamp\n");
}

TEST(DetectionsIo, RoundTrip) {
  const auto dir = test::scratch_dir("detections_io");
  const std::string path = (dir / "detections.csv").string();
  write_detections_csv(path, sample_rows());
  const auto back = read_detections_csv(path);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].frame, 12);
  EXPECT_EQ(back[0].utc, sample_rows()[0].utc);
  EXPECT_DOUBLE_EQ(back[0].u, 640.1235);
  EXPECT_DOUBLE_EQ(back[0].v, 399.5);
  EXPECT_EQ(back[0].area, 17);
  EXPECT_TRUE(back[0].usable());
  EXPECT_FALSE(back[1].usable());
  EXPECT_TRUE(std::isnan(back[1].u));
  EXPECT_EQ(format_detections_csv(back), test::read_text(path));
}

TEST(DetectionsIo, BadInput) {
  const auto dir = test::scratch_dir("detections_io_bad");
  const auto p1 = dir / "a.csv";
  test::write_text(p1, "frame,utc,u,v,peak,area,snr,status\n1,2026-05-01T08:00:00Z,1,2,3,4,5,great\n");
  try {
    read_detections_csv(p1.string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "status");
  }
  const auto p2 = dir / "b.csv";
  test::write_text(p2, "frame,utc,u,v,peak,area,snr,status\n1,yesterday,1,2,3,4,5,ok\n");
  try {
    read_detections_csv(p2.string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.field(), "utc");
  }
  const auto p3 = dir / "c.csv";
  test::write_text(p3, "frame,utc,u,v,peak,area,snr,status\n1,2026-05-01T08:00:00Z,,,,,,ok\n");
  EXPECT_THROW(read_detections_csv(p3.string()), Error);
}
