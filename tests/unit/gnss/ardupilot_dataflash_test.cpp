// ArduPilot DataFlash reader. No real `.bin` log is available: every file here is built by
// tests/support/dataflash_writer from the format's published layout, with known attitude and GPS
// week/ms, so expected UTC and angles are exact.
#include "gnss/formats/ardupilot_dataflash.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "config/error.hpp"
#include "support/dataflash_writer.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

// These logs stamp each GNSS message at its fix's own instant: no receiver lag (its default is
// tested with the gnss stage, tests/unit/pipeline/gnss_stage_test.cpp).
constexpr double kNoLag = 0;

using test::DataflashWriter;

// GPS week 2414 starts on Sunday 2026-04-12 00:00 GPST (1980-01-06 + 2414·7 days), which is
// 2026-04-11 23:59:42 UTC (GPS − UTC = 18 s).
constexpr int kWeek = 2414;
const UtcTime kWeekStartUtc = utc_from_civil(2026, 4, 11, 23, 59, 42, 0);
// Boot time 0 is 3 h 20 min into the week (GPST).
constexpr std::int64_t kBootAtMsOfWeek = 12'000'000;

std::uint32_t ms_of_week(std::uint64_t boot_us) {
  return static_cast<std::uint32_t>(kBootAtMsOfWeek + static_cast<std::int64_t>(boot_us / 1000));
}
UtcTime utc_of_boot(std::int64_t boot_us) {
  return UtcTime{kWeekStartUtc.ns + kBootAtMsOfWeek * 1'000'000 + boot_us * 1000};
}

// GPS at 5 Hz for 20 s from boot 30 s (exact ms), ATT at 25 Hz over the same span.
DataflashWriter flight() {
  DataflashWriter w;
  w.define_att_and_gps();
  for (int i = 0; i < 100; ++i) {
    const std::uint64_t t = 30'000'000 + 200'000ULL * static_cast<std::uint64_t>(i);
    w.gps(t, 3, kWeek, ms_of_week(t));
  }
  for (int i = 0; i < 500; ++i)
    w.att(30'000'000 + 40'000ULL * static_cast<std::uint64_t>(i), 1.5, -2.25, 0.5 * i);
  return w;
}

TEST(DataflashAttitude, KnownAttitudeAndWeekMsGiveExactUtcAndWrappedYaw) {
  AutopilotAttitudeReport r;
  const AttitudeSeries s = dataflash_attitude(flight().bytes(), "flight.bin", &r, kNoLag);
  EXPECT_EQ(r.format, "ardupilot_dataflash");
  EXPECT_EQ(r.attitude_messages, 500u);
  EXPECT_EQ(r.attitude_samples, 500u);
  EXPECT_EQ(r.gps_messages, 100u);
  EXPECT_EQ(r.gps_skipped, 0u);
  EXPECT_EQ(r.fit.used, 100u);
  EXPECT_EQ(r.fit.rejected, 0u);
  EXPECT_EQ(r.fit.residual_max_us, 0);
  EXPECT_EQ(r.truncated_bytes, 0u);
  ASSERT_EQ(s.samples.size(), 500u);
  EXPECT_EQ(s.path, "flight.bin");
  EXPECT_EQ(r.fit.to_utc(0), utc_of_boot(0));
  EXPECT_EQ(format_iso8601_utc(r.fit.to_utc(0), 3), "2026-04-12T03:19:42.000Z");
  for (std::size_t i = 0; i < s.samples.size(); ++i) {
    EXPECT_EQ(s.samples[i].utc, utc_of_boot(30'000'000 + 40'000LL * static_cast<std::int64_t>(i)));
    EXPECT_EQ(s.samples[i].att.roll_deg, 1.5);
    EXPECT_EQ(s.samples[i].att.pitch_deg, -2.25);
    EXPECT_EQ(s.samples[i].att.yaw_deg, wrap_deg_180(0.5 * static_cast<double>(i)));  // 0…249.5 logged
    EXPECT_GT(s.samples[i].att.yaw_deg, -180);
    EXPECT_LE(s.samples[i].att.yaw_deg, 180);
  }
  EXPECT_EQ(s.samples[360].att.yaw_deg, 180);   // 180 stays 180
  EXPECT_EQ(s.samples[362].att.yaw_deg, -179);  // 181 → −179
  EXPECT_EQ(r.utc_start, s.samples.front().utc);
  EXPECT_EQ(r.utc_end, s.samples.back().utc);
}

TEST(DataflashAttitude, OlderIntegerCentidegreeFormatAndGpsInstancesAndSkips) {
  DataflashWriter w;
  // ArduPilot 3.x: angles as int16/uint16 centidegrees; no instance column on GPS.
  w.define(35, "ATT", "QccccCCCC", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw");
  w.define(36, "GPS", "QBIHBcLLeeEefB", "TimeUS,Status,GMS,GWk,NSats,HDop,Lat,Lng,Alt,Spd,GCrs,VZ,T,U");
  for (int i = 0; i < 30; ++i) {
    const std::uint64_t t = 10'000'000 + 200'000ULL * static_cast<std::uint64_t>(i);
    const int status = i < 4 ? 1 : 3;                                 // no fix at first
    const int week = i == 4 ? 0 : kWeek;                              // then a fix without time
    const std::uint32_t ms = ms_of_week(t) + (i == 12 ? 1000u : 0u);  // a one-second jump
    w.message(36, {static_cast<double>(t), static_cast<double>(status), static_cast<double>(ms),
                   static_cast<double>(week), 10, 0.9, 53, -8, 80, 0, 0, 0, 0, 1});
  }
  for (int i = 0; i < 50; ++i)
    w.message(35, {10'000'000.0 + 100'000.0 * i, 0, -12.34, 0, 5.67, 0, 359.99, 0, 0});
  AutopilotAttitudeReport r;
  const AttitudeSeries s = dataflash_attitude(w.bytes(), "old.bin", &r, kNoLag);
  EXPECT_EQ(r.gps_messages, 30u);
  EXPECT_EQ(r.gps_skipped, 5u);
  EXPECT_EQ(r.fit.rejected, 1u);
  EXPECT_EQ(r.fit.used, 24u);
  ASSERT_EQ(s.samples.size(), 50u);
  EXPECT_NEAR(s.samples[0].att.roll_deg, -12.34, 1e-12);
  EXPECT_NEAR(s.samples[0].att.pitch_deg, 5.67, 1e-12);
  EXPECT_NEAR(s.samples[0].att.yaw_deg, -0.01, 1e-9);
  EXPECT_EQ(s.samples[7].utc, utc_of_boot(10'700'000));

  // A second receiver (instance 1), a second late: ignored, not counted.
  DataflashWriter two = flight();
  for (int i = 0; i < 100; ++i) {
    const std::uint64_t t = 30'000'000 + 200'000ULL * static_cast<std::uint64_t>(i);
    two.gps(t, 6, kWeek, ms_of_week(t) + 1000, 1);
  }
  AutopilotAttitudeReport r2;
  dataflash_attitude(two.bytes(), "two.bin", &r2, kNoLag);
  EXPECT_EQ(r2.gps_messages, 100u);
  EXPECT_EQ(r2.fit.rejected, 0u);
  EXPECT_EQ(r2.fit.to_utc(0), utc_of_boot(0));
}

TEST(DataflashAttitude, LongLogFitsTheBootClockDrift) {
  // 10 minutes, boot clock 25 ppm fast (UTC advances 1 − 25e-6 s per boot second), GPS stamps
  // late by 40 ± 2 ms of arrival latency and jitter.
  DataflashWriter w;
  w.define_att_and_gps();
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> jitter(-2000, 2000);
  const auto true_utc = [](double boot_us) {
    return utc_of_boot(0).ns + std::llround(boot_us * 1000 * (1 - 25e-6));
  };
  for (int i = 0; i < 3000; ++i) {
    const double fix_boot_us = 5e6 + 2e5 * i;
    // The fix's time of week in whole ms as the receiver reports it (`frac` before the instant
    // fix_boot_us), and the boot time it arrived.
    const std::int64_t utc_ns = true_utc(fix_boot_us);
    const std::int64_t ms = (utc_ns - kWeekStartUtc.ns) / 1'000'000;
    const double frac_us = static_cast<double>(utc_ns - kWeekStartUtc.ns - ms * 1'000'000) / 1e3;
    const double arrival = fix_boot_us - frac_us + 40'000 + jitter(rng);
    w.gps(static_cast<std::uint64_t>(std::llround(arrival)), 4, kWeek, static_cast<std::uint32_t>(ms));
  }
  for (int i = 0; i < 1000; ++i) w.att(5'000'000 + 600'000ULL * static_cast<std::uint64_t>(i), 0, 0, 90);
  AutopilotAttitudeReport r;
  const AttitudeSeries s = dataflash_attitude(w.bytes(), "long.bin", &r, kNoLag);
  EXPECT_TRUE(r.fit.drift_fitted);
  // 1σ of the fitted slope: 1.15 ms / (√3000 · 173 s) = 0.12 ppm.
  EXPECT_NEAR(r.fit.drift_ppm, -25, 0.4);
  std::cout << "10-minute log: drift " << r.fit.drift_ppm << " ppm (true −25), residual rms "
            << r.fit.residual_rms_us << " us\n";
  EXPECT_NEAR(r.fit.residual_rms_us, 2000 / std::sqrt(3.0), 100);  // uniform ±2 ms
  // The constant 40 ms latency stays in the offset (docs/gnss.md): UTC of a sample is early by it.
  for (std::size_t i = 0; i < s.samples.size(); i += 99) {
    const double boot_us = 5e6 + 6e5 * static_cast<double>(i);
    const double err_ms = static_cast<double>(s.samples[i].utc.ns - true_utc(boot_us)) * 1e-6;
    EXPECT_NEAR(err_ms, -40, 0.3) << i;
  }
}

TEST(DataflashAttitude, TruncatedFilesKeepTheWholeMessages) {
  const std::string full = flight().bytes();
  const std::size_t att_len = 3 + 8 + 8 * 4 + 1;  // QffffffffB
  for (std::size_t cut = 1; cut < att_len; ++cut) {
    AutopilotAttitudeReport r;
    const AttitudeSeries s = dataflash_attitude(full.substr(0, full.size() - cut), "cut.bin", &r, kNoLag);
    EXPECT_EQ(r.truncated_bytes, att_len - cut);
    EXPECT_EQ(s.samples.size(), 499u);
  }
  // Cut inside the first FMT: nothing defined at all.
  try {
    dataflash_attitude(full.substr(0, 50), "cut.bin");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "FMT ATT");
  }
  const DataflashSummary sum = walk_dataflash(full.substr(0, 2), "cut.bin", [](auto&, auto) {});
  EXPECT_EQ(sum.truncated_bytes, 2u);
}

void expect_input_error(const std::string& bytes, const std::string& field, const std::string& reason_part) {
  try {
    dataflash_attitude(bytes, "bad.bin");
    ADD_FAILURE() << "no error; expected " << field << " / " << reason_part;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_EQ(e.file(), "bad.bin");
    EXPECT_EQ(e.line(), 0);
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(e.reason().find(reason_part), std::string::npos) << e.what();
    for (char c : std::string(e.what()))
      EXPECT_FALSE(c >= 0 && c < 0x20) << "control byte echoed: " << e.what();
  }
}

TEST(DataflashBadInput, MissingFmtBadLengthsAndBadHeads) {
  const std::size_t fmt_len = 89;
  {
    DataflashWriter w;  // a message whose type was never defined
    w.define_att_and_gps();
    w.raw(std::string("\xA3\x95\x32", 3) + std::string(20, '\0'));
    expect_input_error(w.bytes(), "type 50",
                       "at byte " + std::to_string(3 * fmt_len) + ": message type 50 has no FMT");
  }
  {
    DataflashWriter w;  // FMT whose Length disagrees with its format
    w.define(35, "ATT", "QffffffffB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF", 40);
    expect_input_error(w.bytes(), "FMT ATT",
                       "at byte 89: type 35 (ATT): Length is 40 bytes but its format 'QffffffffB' takes 44");
  }
  {
    DataflashWriter w;
    w.define(35, "ATT", "QffffffffB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF", 2);
    expect_input_error(w.bytes(), "FMT ATT", "Length is 2 bytes");
  }
  {
    DataflashWriter w;
    w.define(35, "ATT", "Qf", "TimeUS,Roll");
    std::string b = w.bytes();
    b[89 + 9 + 2] = 'X';  // a third format character the format does not have
    b[89 + 25 + 11] = ',';
    b[89 + 25 + 12] = 'B';
    expect_input_error(b, "FMT ATT", "format character 'X'");
  }
  {
    DataflashWriter w;
    w.define(35, "ATT", "Qff", "TimeUS,Roll");
    expect_input_error(w.bytes(), "FMT ATT", "2 column names for 3 format characters");
  }
  {
    DataflashWriter w;
    w.define(35, "AT\x01", "Qf", "TimeUS,Roll");
    expect_input_error(w.bytes(), "FMT AT\\x01", "not printable");
  }
  {
    DataflashWriter w;
    w.define(128, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns", 90);
    expect_input_error(w.bytes(), "FMT FMT", "Length is 90");
  }
  {
    DataflashWriter w;
    w.define_att_and_gps();
    w.define(35, "ATT", "Qf", "TimeUS,Roll");
    expect_input_error(w.bytes(), "FMT ATT", "defined again differently (first definition at byte 89)");
  }
  {
    DataflashWriter w;
    w.define_att_and_gps();
    w.define(40, "GPS", "Q", "TimeUS");
    expect_input_error(w.bytes(), "FMT GPS", "already used by type 36");
  }
  {
    DataflashWriter w = flight();  // garbage between messages
    const std::size_t at = w.bytes().size();
    w.raw("\x01\x02\x03\x04");
    w.att(99'000'000, 0, 0, 0);
    expect_input_error(w.bytes(), "message head",
                       "at byte " + std::to_string(at) + ": expected a message head A3 95, found 01 02");
  }
  expect_input_error(std::string("\xA3\x95\x80", 3) + std::string(86, '\0'), "FMT ", "name is empty");
}

TEST(DataflashBadInput, MissingTypesColumnsAndTime) {
  {
    DataflashWriter w;
    w.define(36, "GPS", "QBBIHBcLLeffffB",
             "TimeUS,I,Status,GMS,GWk,NSats,HDop,Lat,Lng,Alt,Spd,GCrs,VZ,Yaw,U");
    expect_input_error(w.bytes(), "FMT ATT", "no ATT message type");
  }
  {
    DataflashWriter w;
    w.define(35, "ATT", "QffffffffB", "TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF");
    w.att(1'000'000, 0, 0, 0);
    w.att(2'000'000, 0, 0, 0);
    expect_input_error(w.bytes(), "FMT GPS", "no GPS message type");
  }
  {
    DataflashWriter w;
    w.define(35, "ATT", "Qff", "TimeUS,Roll,Pitch");
    w.message(35, {1, 2, 3});
    expect_input_error(w.bytes(), "FMT ATT.Yaw", "at byte 89: type ATT has no column 'Yaw'");
  }
  {
    DataflashWriter w;
    w.define(35, "ATT", "fffff", "TimeUS,Roll,Pitch,Yaw,X");
    w.message(35, {1, 2, 3, 4, 5});
    expect_input_error(w.bytes(), "FMT ATT.TimeUS", "expected an integer");
  }
  {
    DataflashWriter nofix;
    nofix.define_att_and_gps();
    for (int i = 0; i < 20; ++i) nofix.gps(1'000'000ULL * static_cast<std::uint64_t>(i + 1), 2, kWeek, 1000);
    nofix.att(1'000'000, 0, 0, 0);
    nofix.att(2'000'000, 0, 0, 0);
    expect_input_error(nofix.bytes(), "GPS.GMS", "0 message(s) with a 3-D fix");
  }
  {
    DataflashWriter w;
    w.define_att_and_gps();
    for (int i = 0; i < 20; ++i) {
      const std::uint64_t t = 1'000'000ULL * static_cast<std::uint64_t>(i + 1);
      w.gps(t, 3, kWeek, ms_of_week(t));
    }
    w.att(1'000'000, 0, 0, 0);
    w.att(1'000'000, 0, 0, 0);             // not increasing
    w.att(2'000'000, 0, 95, 0);            // pitch out of range
    w.att(3'000'000, std::nan(""), 0, 0);  // NaN
    expect_input_error(w.bytes(), "ATT", "1 usable attitude samples of 4 ATT messages (2 out of range");
  }
}

TEST(DataflashBadInput, DamagedLogsNeverCrash) {
  const std::string full = flight().bytes();
  std::mt19937 rng(99);
  std::size_t errors = 0, results = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::string b = full;
    for (int k = 0; k < 1 + trial % 8; ++k) {
      const std::size_t region = trial % 2 ? 3 * 89 : b.size();
      b[std::uniform_int_distribution<std::size_t>(0, region - 1)(rng)] = static_cast<char>(rng());
    }
    if (trial % 7 == 0) b.resize(std::uniform_int_distribution<std::size_t>(0, b.size())(rng));
    try {
      dataflash_attitude(b, "damaged.bin");
      ++results;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::input);
      ++errors;
    }
  }
  std::cout << "damaged DataFlash logs: " << results << " read, " << errors
            << " rejected with an input error\n";
  EXPECT_GT(errors, 0u);
}

TEST(DataflashFile, ReadsFromDiskAndMissingFileIsAnInputError) {
  const auto dir = test::scratch_dir("dataflash_file");
  test::write_text(dir / "flight.bin", flight().bytes());
  AutopilotAttitudeReport r;
  EXPECT_EQ(read_dataflash_attitude((dir / "flight.bin").string(), &r).samples.size(), 500u);
  EXPECT_EQ(r.file_bytes, flight().bytes().size());
  EXPECT_THROW(read_dataflash_attitude((dir / "missing.bin").string()), Error);
}

}  // namespace
}  // namespace rangecal
