// read_attitude_file picks the reader by content (CSV, PX4 ULog, ArduPilot DataFlash), whatever
// the file is named, and reports what it read.
#include "gnss/formats/attitude_file.hpp"

#include <gtest/gtest.h>

#include "config/error.hpp"
#include "support/dataflash_writer.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

// These logs stamp each GNSS message at its fix's own instant: no receiver lag (its default is
// tested with the gnss stage, tests/unit/pipeline/gnss_stage_test.cpp).
constexpr double kNoLag = 0;

std::string dataflash_bytes() {
  test::DataflashWriter w;
  w.define_att_and_gps();
  for (int i = 0; i < 20; ++i) {
    const std::uint64_t t = 1'000'000 + 200'000ULL * static_cast<std::uint64_t>(i);
    w.gps(t, 3, 2022, static_cast<std::uint32_t>(217'818'000 + t / 1000));
    w.att(t, 1, 2, 270);
  }
  return w.bytes();
}

TEST(AttitudeFile, KindByContent) {
  EXPECT_EQ(attitude_file_kind(std::string("ULog\x01\x12\x35\x01", 8)), AttitudeFileKind::px4_ulog);
  EXPECT_EQ(attitude_file_kind("ULog"), AttitudeFileKind::px4_ulog);  // the parser judges the rest
  EXPECT_EQ(attitude_file_kind(std::string("\xA3\x95\x80", 3)), AttitudeFileKind::ardupilot_dataflash);
  EXPECT_EQ(attitude_file_kind(std::string("\xA3\x95\x23", 3)), AttitudeFileKind::ardupilot_dataflash);
  EXPECT_EQ(attitude_file_kind("utc,roll_deg,pitch_deg,yaw_deg\r\n"), AttitudeFileKind::csv);
  EXPECT_EQ(attitude_file_kind(""), AttitudeFileKind::csv);
  EXPECT_EQ(attitude_file_kind(std::string("PK\x03\x04", 4)), AttitudeFileKind::unknown_binary);
}

TEST(AttitudeFile, EachReaderWhateverTheName) {
  const auto dir = test::scratch_dir("attitude_file");
  // Names that would mislead a reader chosen by extension.
  test::write_text(
      dir / "flight.ulg",
      "utc,roll_deg,pitch_deg,yaw_deg\n2018-10-09T12:00:00Z,1,2,3\n2018-10-09T12:00:01Z,1,2,350\n");
  test::write_text(dir / "attitude.csv", dataflash_bytes());
  test::write_text(dir / "log.bin", test::read_text(test::external("px4-ulog/sample_log_small.ulg")));

  AttitudeFileReport r;
  AttitudeSeries s = read_attitude_file((dir / "flight.ulg").string(), &r);
  EXPECT_EQ(r.kind, AttitudeFileKind::csv);
  EXPECT_FALSE(r.log);
  EXPECT_EQ(r.samples, 2u);
  EXPECT_EQ(format_iso8601_utc(r.utc_start, 0), "2018-10-09T12:00:00Z");

  s = read_attitude_file((dir / "attitude.csv").string(), &r, kNoLag);
  EXPECT_EQ(r.kind, AttitudeFileKind::ardupilot_dataflash);
  ASSERT_TRUE(r.log);
  EXPECT_EQ(r.log->format, "ardupilot_dataflash");
  EXPECT_EQ(r.samples, 20u);
  EXPECT_EQ(s.samples[0].att.yaw_deg, -90);
  // GPS week 2022, 217,818 s into it, is 2018-10-09T12:30:18 GPST = 12:30:00 UTC; boot 1 s later.
  EXPECT_EQ(format_iso8601_utc(r.utc_start, 3), "2018-10-09T12:30:01.000Z");

  s = read_attitude_file((dir / "log.bin").string(), &r, kNoLag);
  EXPECT_EQ(r.kind, AttitudeFileKind::px4_ulog);
  ASSERT_TRUE(r.log);
  EXPECT_EQ(r.log->attitude_samples, 1298u);
  EXPECT_EQ(r.samples, 1298u);
  EXPECT_EQ(s.path, (dir / "log.bin").string());
}

TEST(AttitudeFile, BadFilesAreInputErrors) {
  const auto dir = test::scratch_dir("attitude_file_bad");
  const auto expect_error = [&](const std::string& name, const std::string& bytes,
                                const std::string& needle) {
    test::write_text(dir / name, bytes);
    try {
      read_attitude_file((dir / name).string());
      ADD_FAILURE() << name;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::input);
      EXPECT_EQ(e.file(), (dir / name).string());
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error("zip", std::string("PK\x03\x04\x00\x00 rest", 11), "neither a PX4 ULog");
  expect_error("short.ulg", "ULog\x01\x12", "16-byte");
  expect_error("nofmt.bin", std::string("\xA3\x95\x23", 3) + std::string(40, '\0'), "has no FMT");
  expect_error("empty.csv", "", "");
  try {
    read_attitude_file((dir / "missing").string());
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
  }
}

}  // namespace
}  // namespace rangecal
