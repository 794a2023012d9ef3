// The gnss stage's record (run.json stages.gnss.counts, docs/outputs.md): written and read back
// field for field, each lever-arm form with its own keys, and a malformed value named by its field.
#include "pipeline/io/gnss_record.hpp"

#include <gtest/gtest.h>

#include "config/error.hpp"

namespace rangecal {
namespace {

GnssRecord example() {
  GnssRecord r;
  r.pos_files = {{"a.pos", 1878, "GPST", "ymd", "llh", true}, {"b.pos", 12, "UTC", "week", "xyz", false}};
  r.epochs_read = 1890;
  r.epochs_kept = 444;
  r.dropped_quality = 1434;
  r.dropped_quality_by_q = {{2, 1000}, {5, 434}};
  r.read_by_q = {{1, 456}, {2, 1000}, {5, 434}};
  r.dropped_sd = 7;
  r.dropped_no_attitude = 5;
  r.gap_list = {{"2018-10-09T12:30:00.200000000Z", "2018-10-09T12:30:01.400000000Z", 1.2}};
  r.track_start = "2018-10-09T12:29:00.000000000Z";
  r.track_end = "2018-10-09T12:40:00.000000000Z";
  r.track_span_s = 660.000000001;
  r.lever_arm.source = "body_frd";
  r.lever_arm.body_frd_m = {0.01, -0.02, 0.25};
  r.lever_arm.motion_max_mm_per_ms = 0.1708;
  r.lever_arm.motion_rms_mm_per_ms = 0.0283;
  AttitudeRecord& a = r.attitude.emplace();
  a.path = "log.bin";
  a.format = "dataflash";
  a.samples = 5000;
  a.utc_start = "2018-10-09T12:28:00.000000000Z";
  a.utc_end = "2018-10-09T12:41:00.000000000Z";
  AutopilotLogRecord& l = a.log.emplace();
  l.file_bytes = 123456;
  l.truncated_bytes = 17;
  l.attitude_message = "ATT";
  l.attitude_time_field = "TimeUS";
  l.attitude_messages = 5003;
  l.attitude_invalid = 2;
  l.attitude_not_increasing = 1;
  l.gps_message = "GPS";
  l.gps_messages = 800;
  l.gps_skipped = 3;
  l.gps_used = 795;
  l.gps_rejected = 2;
  l.gps_span_s = 790.5;
  l.boot_zero_utc = "2018-10-09T12:20:00.123456789Z";
  l.offset_ns = 1539087600123456789;
  l.offset_ref_boot_us = -42;
  l.drift_fitted = true;
  l.drift_ppm = -3.25;
  l.residual_rms_us = 410.5;
  l.residual_max_us = 990.25;
  l.reject_threshold_us = 5000;
  l.gnss_lag_ms = 120;
  l.gnss_lag_source = "default for dataflash";
  return r;
}

GnssRecord through_text(const GnssRecord& r) {
  return parse_gnss_record(nlohmann::json::parse(gnss_record_json(r).dump(2)), "run.json",
                           "stages.gnss.counts");
}

TEST(GnssRecord, RoundTripsEveryField) {
  const GnssRecord r = example();
  const GnssRecord back = through_text(r);
  ASSERT_EQ(back.pos_files.size(), 2u);
  EXPECT_EQ(back.pos_files[0].path, "a.pos");
  EXPECT_EQ(back.pos_files[0].epochs, 1878u);
  EXPECT_EQ(back.pos_files[1].position_format, "xyz");
  EXPECT_TRUE(back.pos_files[0].velocity);
  EXPECT_FALSE(back.pos_files[1].velocity);
  EXPECT_EQ(back.epochs_read, 1890u);
  EXPECT_EQ(back.dropped_quality_by_q, r.dropped_quality_by_q);
  EXPECT_EQ(back.read_by_q, r.read_by_q);
  ASSERT_EQ(back.gap_list.size(), 1u);
  EXPECT_EQ(back.gap_list[0].duration_s, 1.2);
  EXPECT_EQ(back.track_span_s, 660.000000001);
  EXPECT_EQ(back.lever_arm.body_frd_m, r.lever_arm.body_frd_m);
  EXPECT_EQ(back.lever_arm.motion_rms_mm_per_ms, 0.0283);
  ASSERT_TRUE(back.attitude && back.attitude->log);
  EXPECT_EQ(back.attitude->samples, 5000u);
  EXPECT_EQ(back.attitude->log->offset_ns, 1539087600123456789);
  EXPECT_EQ(back.attitude->log->offset_ref_boot_us, -42);
  EXPECT_TRUE(back.attitude->log->drift_fitted);
  EXPECT_EQ(back.attitude->log->drift_ppm, -3.25);
  EXPECT_EQ(back.attitude->log->gnss_lag_source, "default for dataflash");
  // Every field: what is read back writes the same text.
  EXPECT_EQ(gnss_record_json(back).dump(2), gnss_record_json(r).dump(2));
  // `gaps` is the gap list's length.
  EXPECT_EQ(gnss_record_json(r).at("gaps"), 1);
}

TEST(GnssRecord, EachLeverArmFormWritesItsOwnKeysAndACsvAttitudeHasNoLog) {
  GnssRecord r = example();
  r.lever_arm = LeverArmRecord{};
  r.lever_arm.source = "total_station";
  r.lever_arm.vertical_m = 0.252;
  r.lever_arm.vertical_sd_m = 0.0028;
  r.lever_arm.sessions = 2;
  r.lever_arm.vertical_form_max_error_m = 0.0041;
  r.lever_arm.vertical_form_epochs_over_5mm = 3;
  r.attitude->log.reset();
  const nlohmann::json j = gnss_record_json(r);
  EXPECT_FALSE(j["lever_arm"].contains("body_frd_m"));
  EXPECT_EQ(j["lever_arm"]["sessions"], 2);
  EXPECT_FALSE(j["attitude"].contains("gnss_lag_ms"));
  const GnssRecord back = through_text(r);
  EXPECT_EQ(back.lever_arm.vertical_sd_m, 0.0028);
  EXPECT_EQ(back.lever_arm.vertical_form_epochs_over_5mm, 3u);
  EXPECT_FALSE(back.attitude->log);
  EXPECT_EQ(gnss_record_json(back).dump(2), j.dump(2));
  r.lever_arm.source = "vertical";
  EXPECT_FALSE(gnss_record_json(r)["lever_arm"].contains("sessions"));
}

TEST(GnssRecord, AWrongTypeNamesItsField) {
  nlohmann::json j = gnss_record_json(example());
  j["attitude"]["gps_used"] = -1;
  try {
    parse_gnss_record(j, "/out/run.json", "stages.gnss.counts");
    FAIL() << "a negative count was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "/out/run.json");
    EXPECT_EQ(e.field(), "stages.gnss.counts.attitude.gps_used");
  }
  j = gnss_record_json(example());
  j["read_by_q"]["fix"] = 3;
  try {
    parse_gnss_record(j, "/out/run.json", "stages.gnss.counts");
    FAIL() << "a quality that is not a number was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "stages.gnss.counts.read_by_q.fix");
  }
}

}  // namespace
}  // namespace rangecal
