// PX4 ULog reader: the two real logs of external/px4-ulog (counts of SOURCE.md, attitude on UTC
// against an independent decoding written here), synthetic logs for nested formats, padding,
// appended data and truncation, and malformed input of many kinds (always rangecal::Error, input).
#include "gnss/formats/px4_ulog.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <map>
#include <random>

#include "config/error.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

// These logs stamp each GNSS message at its fix's own instant: no receiver lag (its default is
// tested with the gnss stage, tests/unit/pipeline/gnss_stage_test.cpp).
constexpr double kNoLag = 0;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

std::string sample(const std::string& name) {
  return test::external("px4-ulog/" + name).string();
}

// ---- an independent minimal ULog walk ---------------------------------------------------------
// Written from the "ULog File Format" page only, sharing nothing with the reader: message headers,
// F texts, A msg_id → topic, D payloads of multi_id 0; field offsets of flat formats by summing
// the C type sizes.

std::uint64_t le(const std::string& b, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int i = n - 1; i >= 0; --i)
    v = v << 8 | static_cast<unsigned char>(b[at + static_cast<std::size_t>(i)]);
  return v;
}

struct Walk {
  std::map<std::string, std::string> formats;            // name → fields text
  std::map<std::string, std::vector<std::string>> data;  // topic (multi_id 0) → payloads
  std::size_t last_message_start = 0;
};

Walk walk(const std::string& b) {
  Walk w;
  std::map<std::uint64_t, std::pair<std::string, int>> subs;
  std::size_t p = 16;
  while (p + 3 <= b.size()) {
    const std::size_t size = le(b, p, 2);
    const char type = b[p + 2];
    if (p + 3 + size > b.size()) break;
    w.last_message_start = p;
    const std::string body = b.substr(p + 3, size);
    if (type == 'F') {
      const std::size_t c = body.find(':');
      w.formats[body.substr(0, c)] = body.substr(c + 1);
    } else if (type == 'A') {
      subs[le(body, 1, 2)] = {body.substr(3), static_cast<unsigned char>(body[0])};
    } else if (type == 'D') {
      const auto& s = subs.at(le(body, 0, 2));
      if (s.second == 0) w.data[s.first].push_back(body.substr(2));
    }
    p += 3 + size;
  }
  return w;
}

// Offset of field `name` in a format of base-type fields; npos when absent.
std::size_t offset_of(const std::string& fields, const std::string& name) {
  const std::map<std::string, std::size_t> sizes = {
      {"int8_t", 1},  {"uint8_t", 1},  {"bool", 1},  {"char", 1},    {"int16_t", 2},  {"uint16_t", 2},
      {"int32_t", 4}, {"uint32_t", 4}, {"float", 4}, {"int64_t", 8}, {"uint64_t", 8}, {"double", 8}};
  std::size_t off = 0, start = 0;
  while (start < fields.size()) {
    const std::size_t semi = fields.find(';', start);
    const std::string f = fields.substr(start, semi - start);
    start = semi + 1;
    const std::size_t sp = f.find(' ');
    std::string type = f.substr(0, sp);
    std::size_t n = 1;
    if (const std::size_t lb = type.find('['); lb != std::string::npos) {
      n = std::stoul(type.substr(lb + 1));
      type = type.substr(0, lb);
    }
    if (f.substr(sp + 1) == name) return off;
    off += sizes.at(type) * n;
  }
  return std::string::npos;
}

float f32(const std::string& b, std::size_t at) {
  const auto bits = static_cast<std::uint32_t>(le(b, at, 4));
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

struct Truth {
  std::vector<std::int64_t> utc_ns;
  std::vector<Attitude> att;
  std::size_t gps_messages = 0, gps_no_fix = 0;
};

// Attitude on UTC by the independent walk: Euler angles from the rotation matrix of q (pitch by
// atan2, not asin), boot → UTC offset = mean of (time_utc_usec − timestamp) over the fixes.
Truth independent(const std::string& path) {
  const std::string b = test::read_text(path);
  const Walk w = walk(b);
  Truth t;
  const std::string& gf = w.formats.at("vehicle_gps_position");
  const std::size_t g_ts = offset_of(gf, "timestamp"), g_utc = offset_of(gf, "time_utc_usec"),
                    g_fix = offset_of(gf, "fix_type"), g_rel = offset_of(gf, "timestamp_time_relative");
  long double sum = 0;
  std::size_t n = 0;
  for (const std::string& d : w.data.at("vehicle_gps_position")) {
    ++t.gps_messages;
    const std::uint64_t utc = le(d, g_utc, 8);
    if (static_cast<unsigned char>(d[g_fix]) < 3 || utc == 0) {
      ++t.gps_no_fix;
      continue;
    }
    const auto rel = static_cast<std::int32_t>(le(d, g_rel, 4));
    sum += static_cast<long double>(static_cast<std::int64_t>(utc) -
                                    static_cast<std::int64_t>(le(d, g_ts, 8)) - rel);
    ++n;
  }
  const long double offset_us = sum / n;
  const std::string& af = w.formats.at("vehicle_attitude");
  const std::size_t a_q = offset_of(af, "q");
  std::size_t a_t = offset_of(af, "timestamp_sample");
  if (a_t == std::string::npos) a_t = offset_of(af, "timestamp");
  for (const std::string& d : w.data.at("vehicle_attitude")) {
    const auto boot = static_cast<std::int64_t>(le(d, a_t, 8));
    t.utc_ns.push_back(std::llround((static_cast<long double>(boot) + offset_us) * 1000));
    double q[4];
    for (int i = 0; i < 4; ++i) q[i] = f32(d, a_q + 4 * static_cast<std::size_t>(i));
    const double s = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    const double w0 = q[0] / s, x = q[1] / s, y = q[2] / s, z = q[3] / s;
    const double r00 = w0 * w0 + x * x - y * y - z * z, r10 = 2 * (x * y + w0 * z),
                 r20 = 2 * (x * z - w0 * y), r21 = 2 * (y * z + w0 * x),
                 r22 = w0 * w0 - x * x - y * y + z * z;
    Attitude a;
    a.roll_deg = std::atan2(r21, r22) / kDeg;
    a.pitch_deg = std::atan2(-r20, std::hypot(r21, r22)) / kDeg;
    a.yaw_deg = std::atan2(r10, r00) / kDeg;
    t.att.push_back(a);
  }
  return t;
}

void expect_matches_independent(const std::string& path, const AttitudeSeries& s) {
  const Truth t = independent(path);
  ASSERT_EQ(s.samples.size(), t.att.size());
  double worst_deg = 0;
  std::int64_t worst_ns = 0;
  for (std::size_t i = 0; i < t.att.size(); ++i) {
    const Attitude& a = s.samples[i].att;
    worst_deg = std::max({worst_deg, std::abs(a.roll_deg - t.att[i].roll_deg),
                          std::abs(a.pitch_deg - t.att[i].pitch_deg),
                          std::abs(wrap_deg_180(a.yaw_deg - t.att[i].yaw_deg))});
    worst_ns = std::max(worst_ns, std::abs(s.samples[i].utc.ns - t.utc_ns[i]));
    EXPECT_GT(a.yaw_deg, -180);
    EXPECT_LE(a.yaw_deg, 180);
  }
  EXPECT_LT(worst_deg, 1e-6);
  EXPECT_LE(worst_ns, 1000);  // 1 µs
  std::cout << path << ": worst angle difference " << worst_deg << " deg, worst time difference " << worst_ns
            << " ns\n";
}

TEST(Px4UlogReal, SampleLogSmallSummary) {
  const UlogLog log = read_ulog(sample("sample_log_small.ulg"));
  const UlogSummary& s = log.summary;
  EXPECT_EQ(s.file_bytes, 921631u);
  EXPECT_EQ(s.version, 1);
  EXPECT_EQ(s.info_value("sys_name"), "PX4");
  EXPECT_EQ(s.info_value("ver_hw"), "CUBEPILOT_CUBEORANGE");
  EXPECT_EQ(s.info_value("ver_sw"), "8583f1da30b63154d6ba0bc187d86135dfe33cf9");
  EXPECT_EQ(s.info_value("ver_sw_branch"), "v1.11.2_w_rc_sysid");
  EXPECT_EQ(s.info.size(), 14u);
  EXPECT_EQ(s.parameters, 980u);
  EXPECT_EQ(s.topics.size(), 72u);
  EXPECT_EQ(s.dropouts, 1u);
  EXPECT_EQ(s.dropout_ms, 30u);
  EXPECT_EQ(s.truncated_bytes, 0u);
  EXPECT_EQ(s.unknown_messages, 0u);
  EXPECT_EQ(s.syncs, 12u);
  EXPECT_EQ(s.logged_strings, 3u);
  EXPECT_EQ(log.data.size(), 14604u);
  ASSERT_TRUE(s.last_timestamp_us);
  EXPECT_EQ(*s.last_timestamp_us, 1194367328u);
  EXPECT_LT(*s.first_timestamp_us, *s.last_timestamp_us);
  std::map<std::string, std::size_t> count;
  for (const UlogTopicCount& t : s.topics) count[t.topic + "/" + std::to_string(t.multi_id)] = t.messages;
  EXPECT_EQ(count.at("vehicle_attitude/0"), 1298u);
  EXPECT_EQ(count.at("vehicle_gps_position/0"), 32u);
  EXPECT_EQ(count.at("sensor_accel/2"), 6u);
}

TEST(Px4UlogReal, SampleLogSmallAttitudeOnUtc) {
  AutopilotAttitudeReport r;
  const AttitudeSeries s = read_ulog_attitude(sample("sample_log_small.ulg"), &r, kNoLag);
  EXPECT_EQ(r.format, "px4_ulog");
  EXPECT_EQ(r.attitude_messages, 1298u);
  EXPECT_EQ(r.attitude_samples, 1298u);
  EXPECT_EQ(r.attitude_time_field, "timestamp");
  EXPECT_EQ(r.gps_message, "vehicle_gps_position");
  EXPECT_EQ(r.gps_messages, 32u);
  EXPECT_EQ(r.gps_skipped, 0u);
  EXPECT_EQ(r.fit.used, 32u);
  EXPECT_EQ(r.fit.rejected, 0u);     // so the independent mean below is the same estimator
  EXPECT_FALSE(r.fit.drift_fitted);  // 6.2 s of GPS
  // Arrival jitter of a real u-blox on a CubeOrange: a few ms.
  EXPECT_GT(r.fit.residual_rms_us, 1000);
  EXPECT_LT(r.fit.residual_max_us, r.fit.reject_threshold_us);
  std::cout << "sample_log_small: residual rms " << r.fit.residual_rms_us << " us, max "
            << r.fit.residual_max_us << " us, threshold " << r.fit.reject_threshold_us << " us, UTC "
            << format_iso8601_utc(r.utc_start, 6) << " … " << format_iso8601_utc(r.utc_end, 6) << "\n";
  // The flight date (SOURCE.md).
  EXPECT_EQ(format_iso8601_utc(s.samples.front().utc, 0).substr(0, 10), "2021-04-21");
  EXPECT_EQ(format_iso8601_utc(s.samples.back().utc, 0).substr(0, 10), "2021-04-21");
  EXPECT_EQ(r.utc_start, s.samples.front().utc);
  expect_matches_independent(sample("sample_log_small.ulg"), s);
}

TEST(Px4UlogReal, EventsLogUsesTimestampSampleAndSkipsNoFix) {
  const std::string path = sample("sample_px4_events.ulg");
  AutopilotAttitudeReport r;
  const AttitudeSeries s = read_ulog_attitude(path, &r, kNoLag);
  const Truth t = independent(path);
  EXPECT_EQ(r.attitude_messages, 622u);
  EXPECT_EQ(r.attitude_samples, 622u);
  EXPECT_EQ(r.attitude_time_field, "timestamp_sample");
  EXPECT_EQ(r.gps_message, "vehicle_gps_position");
  EXPECT_EQ(r.gps_messages, 583u);
  EXPECT_EQ(t.gps_messages, 583u);
  EXPECT_EQ(r.gps_skipped, t.gps_no_fix);
  EXPECT_GT(r.gps_skipped, 0u);
  EXPECT_EQ(r.fit.used + r.fit.rejected + r.gps_skipped, 583u);
  EXPECT_EQ(r.fit.rejected, 0u);
  std::cout << "sample_px4_events: GPS " << r.gps_messages << ", no fix " << r.gps_skipped << ", used "
            << r.fit.used << ", residual rms " << r.fit.residual_rms_us << " us\n";
  // SITL: its boot clock is Unix time, so boot time maps to UTC with offset 0 (2024-03-18).
  EXPECT_EQ(r.fit.to_utc(0).ns, 0);
  EXPECT_EQ(format_iso8601_utc(s.samples.front().utc, 0).substr(0, 10), "2024-03-18");
  expect_matches_independent(path, s);
  const UlogLog log = read_ulog(path);
  EXPECT_EQ(log.summary.default_parameters, 62u);
  EXPECT_EQ(log.summary.info_value("ver_hw"), "PX4_SITL");
}

TEST(Px4UlogReal, TruncatedRealLogStopsAtTheLastWholeMessage) {
  const std::string full = test::read_text(sample("sample_log_small.ulg"));
  for (std::size_t cut : {std::size_t{100}, std::size_t{1}, std::size_t{333333}}) {
    const std::string b = full.substr(0, full.size() - cut);
    const Walk w = walk(b);
    const std::size_t last_end = w.last_message_start + 3 + le(b, w.last_message_start, 2);
    const UlogLog log = parse_ulog(b, "cut.ulg");
    EXPECT_EQ(log.summary.truncated_bytes, b.size() - last_end) << cut;
    EXPECT_GT(log.summary.truncated_bytes, 0u);
    AutopilotAttitudeReport r;
    const AttitudeSeries s = ulog_attitude(log, &r, kNoLag);
    EXPECT_EQ(s.samples.size(), w.data.at("vehicle_attitude").size());
    EXPECT_EQ(r.truncated_bytes, log.summary.truncated_bytes);
  }
}

// ---- synthetic logs ---------------------------------------------------------------------------

void put(std::string& s, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i) s += static_cast<char>(v >> (8 * i) & 0xff);
}
std::string bytes_of(float f) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, 4);
  std::string s;
  put(s, bits, 4);
  return s;
}
std::string bytes_of(double d) {
  std::uint64_t bits;
  std::memcpy(&bits, &d, 8);
  std::string s;
  put(s, bits, 8);
  return s;
}

// Builds a ULog message by message, from "ULog File Format".
struct UlogBuilder {
  std::string b;
  explicit UlogBuilder(int version = 1, bool flag_bits = true) {
    b = std::string("ULog\x01\x12\x35", 7);
    b += static_cast<char>(version);
    put(b, 1'000'000, 8);
    if (flag_bits) msg('B', std::string(40, '\0'));
  }
  void msg(char type, const std::string& body) {
    put(b, body.size(), 2);
    b += type;
    b += body;
  }
  void fmt(const std::string& text) { msg('F', text); }
  void add(int multi, int id, const std::string& topic) {
    std::string s(1, static_cast<char>(multi));
    put(s, static_cast<std::uint64_t>(id), 2);
    msg('A', s + topic);
  }
  void data(int id, const std::string& payload) {
    std::string s;
    put(s, static_cast<std::uint64_t>(id), 2);
    msg('D', s + payload);
  }
  void info(const std::string& key, const std::string& value) {
    msg('I', std::string(1, static_cast<char>(key.size())) + key + value);
  }
};

const UtcTime kBootZero = utc_from_civil(2026, 5, 14, 9, 0, 0, 0);

// vehicle_attitude (trailing padding not logged) and sensor_gps, attitude at 50 Hz for 10 s, GPS at
// 5 Hz with exact UTC; `q_of(i)` gives each sample's attitude.
UlogBuilder attitude_log(bool with_gps = true) {
  UlogBuilder u;
  u.info("char[3] sys_name", "PX4");
  u.fmt("vehicle_attitude:uint64_t timestamp;float[4] q;uint8_t[4] _padding0;");
  u.fmt("sensor_gps:uint64_t timestamp;uint64_t time_utc_usec;uint8_t fix_type;uint8_t[7] _padding0;");
  u.add(0, 3, "vehicle_attitude");
  if (with_gps) u.add(1, 4, "sensor_gps");
  return u;
}

std::string attitude_payload(std::uint64_t t_us, const Attitude& a) {
  const Eigen::Quaterniond q(rotation_nb(a));
  std::string p;
  put(p, t_us, 8);
  for (double c : {q.w(), q.x(), q.y(), q.z()}) p += bytes_of(static_cast<float>(c));
  return p;
}

std::string gps_payload(std::uint64_t t_us, std::uint64_t utc_us, int fix) {
  std::string p;
  put(p, t_us, 8);
  put(p, utc_us, 8);
  p += static_cast<char>(fix);
  return p;
}

std::uint64_t utc_us_of_boot(std::uint64_t t_us) {
  return static_cast<std::uint64_t>(kBootZero.ns / 1000) + t_us;
}

TEST(Px4UlogSynthetic, AttitudeGpsSkipsRejectsAndYawWrap) {
  UlogBuilder u = attitude_log();
  for (int i = 0; i < 50; ++i) {
    const std::uint64_t t = 5'000'000 + 200'000ULL * static_cast<std::uint64_t>(i);
    std::uint64_t utc = utc_us_of_boot(t);
    int fix = 3;
    if (i == 3) fix = 2;            // no 3-D fix
    if (i == 4) utc = 0;            // no time
    if (i == 20) utc += 1'000'000;  // a jump
    u.data(4, gps_payload(t, utc, fix));
  }
  std::vector<Attitude> truth;
  for (int i = 0; i < 500; ++i) {
    const double yaw = 170 + 0.04 * i;  // crosses 180°
    truth.push_back({5 * std::sin(i * 0.01), -3 + 0.01 * i, yaw});
    u.data(3, attitude_payload(5'000'000 + 20'000ULL * static_cast<std::uint64_t>(i), truth.back()));
  }
  std::string zero_q;
  put(zero_q, 20'000'000, 8);
  zero_q += std::string(16, '\0');
  u.data(3, zero_q);                                  // not a quaternion
  u.data(3, attitude_payload(5'000'000, {0, 0, 0}));  // time going back
  AutopilotAttitudeReport r;
  const AttitudeSeries s = ulog_attitude(parse_ulog(u.b, "synthetic.ulg"), &r, kNoLag);
  EXPECT_EQ(r.gps_message, "sensor_gps");
  EXPECT_EQ(r.gps_messages, 50u);
  EXPECT_EQ(r.gps_skipped, 2u);
  EXPECT_EQ(r.fit.rejected, 1u);
  EXPECT_EQ(r.fit.used, 47u);
  EXPECT_EQ(r.fit.residual_max_us, 0);
  EXPECT_EQ(r.attitude_messages, 502u);
  EXPECT_EQ(r.attitude_invalid, 1u);
  EXPECT_EQ(r.attitude_not_increasing, 1u);
  ASSERT_EQ(s.samples.size(), 500u);
  EXPECT_EQ(s.path, "synthetic.ulg");
  for (std::size_t i = 0; i < 500; ++i) {
    EXPECT_EQ(s.samples[i].utc.ns,
              kBootZero.ns + (5'000'000 + 20'000LL * static_cast<std::int64_t>(i)) * 1000);
    EXPECT_NEAR(s.samples[i].att.roll_deg, truth[i].roll_deg, 1e-4);  // float quaternion
    EXPECT_NEAR(s.samples[i].att.pitch_deg, truth[i].pitch_deg, 1e-4);
    EXPECT_NEAR(wrap_deg_180(s.samples[i].att.yaw_deg - truth[i].yaw_deg), 0, 1e-4);
    EXPECT_GT(s.samples[i].att.yaw_deg, -180);
    EXPECT_LE(s.samples[i].att.yaw_deg, 180);
  }
  EXPECT_NEAR(s.samples.back().att.yaw_deg, wrap_deg_180(170 + 0.04 * 499), 1e-4);
}

TEST(Px4UlogSynthetic, NestedFormatsArraysAndPadding) {
  UlogBuilder u;
  // inner: 2 + 3 + 3 (padding, kept inside a nested format) = 8 bytes.
  u.fmt("inner:uint16_t a;int8_t[3] b;uint8_t[3] _padding0;");
  // outer: 8 + 2·8 + 8 + 4 + 4 (trailing padding, not logged) = 40 bytes, 36 logged.
  u.fmt("outer:uint64_t timestamp;inner[2] c;double x;float y;uint8_t[4] _padding0;");
  // "Format Message": a type may be used before it is defined.
  u.fmt("early:uint64_t timestamp;late[2] x;");
  u.fmt("late:uint8_t v;");
  u.add(0, 9, "outer");
  std::string p;
  put(p, 777, 8);
  for (int k = 0; k < 2; ++k) {
    put(p, 1000 + static_cast<std::uint64_t>(k), 2);
    p += std::string{static_cast<char>(-1 - k), 2, 3};
    p += std::string(3, '\0');
  }
  p += bytes_of(-2.5);
  p += bytes_of(1.25f);
  u.data(9, p);
  u.data(9, p + std::string(4, '\0'));  // padding written after all: accepted
  const UlogLog log = parse_ulog(u.b, "nested.ulg");
  ASSERT_EQ(log.formats.size(), 4u);
  EXPECT_EQ(log.formats[2].size, 10u);
  const UlogFormat& outer = log.formats[1];
  EXPECT_EQ(outer.size, 40u);
  EXPECT_EQ(outer.logged_size, 36u);
  EXPECT_EQ(log.formats[0].size, 8u);
  EXPECT_EQ(log.formats[0].logged_size, 5u);
  ASSERT_EQ(outer.fields.size(), 5u);
  EXPECT_EQ(outer.fields[1].type, UlogType::nested);
  EXPECT_EQ(outer.fields[1].count, 2u);
  EXPECT_EQ(outer.fields[1].size, 16u);
  EXPECT_EQ(outer.fields[2].offset, 24u);
  const auto b = find_ulog_field(log, 1, "c.b");
  ASSERT_TRUE(b);
  EXPECT_EQ(b->offset, 10u);
  EXPECT_EQ(b->count, 3u);
  EXPECT_FALSE(find_ulog_field(log, 1, "c.zz"));
  EXPECT_FALSE(find_ulog_field(log, 1, "x.y"));
  ASSERT_EQ(log.data.size(), 2u);
  EXPECT_EQ(ulog_number(log, log.data[0], *b, 0), -1);
  EXPECT_EQ(ulog_number(log, log.data[0], *b, 2), 3);
  EXPECT_EQ(ulog_number(log, log.data[0], *find_ulog_field(log, 1, "c.a"), 0), 1000);
  EXPECT_EQ(ulog_number(log, log.data[0], *find_ulog_field(log, 1, "x")), -2.5);
  EXPECT_EQ(ulog_number(log, log.data[0], *find_ulog_field(log, 1, "y")), 1.25);
  EXPECT_THROW(ulog_number(log, log.data[0], *b, 3), Error);
  EXPECT_EQ(*log.summary.first_timestamp_us, 777u);
  ASSERT_EQ(log.summary.topics.size(), 1u);
  EXPECT_EQ(log.summary.topics[0].messages, 2u);
}

TEST(Px4UlogSynthetic, AppendedDataIsReadAfterAnInterruptedMessage) {
  UlogBuilder u(1, false);
  std::string flags(40, '\0');
  flags[8] = 1;  // DATA_APPENDED
  const std::size_t flags_at = u.b.size() + 3;
  u.msg('B', flags);
  u.fmt("t:uint64_t timestamp;");
  u.add(0, 1, "t");
  std::string p;
  put(p, 5, 8);
  u.data(1, p);
  u.b += std::string("\x0a\x00", 2) + "D";  // a D message the logger never finished
  const std::size_t appended = u.b.size();
  u.data(1, p);
  u.data(1, p);
  for (int i = 0; i < 8; ++i)
    u.b[flags_at + 16 + static_cast<std::size_t>(i)] = static_cast<char>(appended >> (8 * i));
  const UlogLog log = parse_ulog(u.b, "appended.ulg");
  EXPECT_TRUE(log.summary.data_appended);
  EXPECT_EQ(log.data.size(), 3u);
  EXPECT_EQ(log.summary.truncated_bytes, 3u);
}

TEST(Px4UlogSynthetic, TruncatedLastMessageIsCountedNotAnError) {
  UlogBuilder u = attitude_log();
  for (int i = 0; i < 10; ++i) {
    const std::uint64_t t = 1'000'000ULL * static_cast<std::uint64_t>(i + 1);
    u.data(4, gps_payload(t, utc_us_of_boot(t), 3));
    u.data(3, attitude_payload(t, {1, 2, 3}));
  }
  for (std::size_t cut = 1; cut < 27; ++cut) {  // the last D message is 3 + 2 + 24 bytes
    const UlogLog log = parse_ulog(u.b.substr(0, u.b.size() - cut), "cut.ulg");
    EXPECT_EQ(log.summary.truncated_bytes, 29 - cut) << cut;
    EXPECT_EQ(ulog_attitude(log).samples.size(), 9u);
  }
}

// ---- malformed input --------------------------------------------------------------------------

void expect_input_error(const std::string& bytes, const std::string& field_part,
                        const std::string& reason_part) {
  try {
    const UlogLog log = parse_ulog(bytes, "bad.ulg");
    ulog_attitude(log);
    ADD_FAILURE() << "no error; expected " << field_part << " / " << reason_part;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_EQ(e.file(), "bad.ulg");
    EXPECT_EQ(e.line(), 0);
    EXPECT_NE(e.field().find(field_part), std::string::npos) << e.what();
    EXPECT_NE(e.reason().find(reason_part), std::string::npos) << e.what();
    for (char c : std::string(e.what()))
      EXPECT_FALSE(c >= 0 && c < 0x20) << "control byte echoed: " << e.what();
  }
}

TEST(Px4UlogBadInput, HeaderAndMagic) {
  const std::string ok = UlogBuilder().b;
  expect_input_error(ok.substr(0, 10), "header", "16-byte");
  expect_input_error("", "header", "0 bytes");
  std::string magic = ok;
  magic[6] = 0x36;
  expect_input_error(magic, "header", "magic");
  expect_input_error("PK\x03\x04 this is a zip, not a log", "header", "magic");
  // "Requirements for Parsers": a future version is parsed as well, and reported.
  EXPECT_EQ(parse_ulog(UlogBuilder(2).b, "v2.ulg").summary.version, 2);
}

TEST(Px4UlogBadInput, Formats) {
  const auto with = [](const std::string& fmt) {
    UlogBuilder u;
    u.fmt(fmt);
    u.add(0, 1, "foo");
    return u.b;
  };
  // The F message starts after the header (16) and the B message (3 + 40).
  expect_input_error(with("foo:uint64_t timestamp;bar_t x;"), "F foo.x", "at byte 59: type 'bar_t'");
  expect_input_error(with("foo:uint64_t timestamp;foo x;"), "F foo", "contains itself");
  expect_input_error(with("foo:uint8_t[60000] a;uint8_t[60000] b;"), "F foo.b", "65533");
  expect_input_error(with("foo:uint8_t[999999] a;"), "F foo", "at most 5 digits");
  expect_input_error(with("foo:uint8_t[] a;"), "F foo", "not a number");
  expect_input_error(with("foo:uint64_ttimestamp;"), "F foo", "'type name'");
  expect_input_error(with("foo:uint64_t timestamp;uint8_t timestamp;"), "F foo.timestamp", "twice");
  expect_input_error(with("no colon here"), "F", "name:type field");
  expect_input_error(with(std::string("fo\x01o:uint64_t timestamp;", 23)), "F", "fo\\x01o");
  {
    UlogBuilder u;  // a chain of 40 nested formats
    for (int i = 0; i < 40; ++i) u.fmt("n" + std::to_string(i) + ":n" + std::to_string(i + 1) + " x;");
    u.fmt("n40:uint8_t x;");
    expect_input_error(u.b, "F n", "nested more than 32");
  }
  {
    UlogBuilder u;
    u.fmt("foo:uint64_t timestamp;");
    u.fmt("foo:uint32_t timestamp;");
    expect_input_error(u.b, "F foo", "second time");
  }
}

TEST(Px4UlogBadInput, SubscriptionsAndData) {
  UlogBuilder base;
  base.fmt("foo:uint64_t timestamp;uint32_t v;");
  {
    UlogBuilder u = base;
    u.add(0, 1, "nope");
    expect_input_error(u.b, "A nope", "no format");
  }
  {
    UlogBuilder u = base;
    u.add(0, 1, "foo");
    std::string p(12, '\0');
    u.data(1, p);
    const std::size_t at = u.b.size();
    u.data(7, p);
    expect_input_error(u.b, "D", "at byte " + std::to_string(at) + ": msg_id 7 has no subscription");
  }
  {
    UlogBuilder u = base;
    u.add(0, 1, "foo");
    u.data(1, std::string(4, '\0'));  // shorter than its format
    expect_input_error(u.b, "D foo", "carries 4 data bytes, its format takes 12");
  }
  {
    UlogBuilder u = base;
    u.add(0, 1, "foo");
    u.data(1, std::string(13, '\0'));
    expect_input_error(u.b, "D foo", "carries 13");
  }
  {
    UlogBuilder u = base;
    u.add(0, 1, "foo");
    u.add(0, 1, "foo");
    expect_input_error(u.b, "A foo", "already subscribed");
  }
  {
    UlogBuilder u = base;
    u.add(0, 1, "foo");
    u.msg('R', std::string("\x01\x00", 2));
    u.data(1, std::string(12, '\0'));
    expect_input_error(u.b, "D", "no subscription");
  }
  {
    UlogBuilder u = base;
    u.msg('R', std::string("\x05\x00", 2));
    expect_input_error(u.b, "R", "not subscribed");
  }
  {
    UlogBuilder u = base;
    u.msg('D', "\x01");
    expect_input_error(u.b, "D", "fewer than the 2");
  }
  {
    UlogBuilder u = base;
    u.msg('A', "\x00\x01");
    expect_input_error(u.b, "A", "fewer than the 4");
  }
}

TEST(Px4UlogBadInput, OtherMessages) {
  {
    UlogBuilder u;  // I key length running past the message body
    u.msg('I', std::string(1, static_cast<char>(40)) + "char[3] sys_name");
    expect_input_error(u.b, "I", "key length 40 runs past");
  }
  {
    UlogBuilder u;
    u.info("char[3] sys_name", "PX");  // value shorter than its type
    expect_input_error(u.b, "I sys_name", "value is 2 bytes");
  }
  {
    UlogBuilder u;
    u.info("foo_t x", "abc");
    expect_input_error(u.b, "I x", "not a ULog base type");
  }
  {
    UlogBuilder u;
    u.msg('O', "\x01");
    expect_input_error(u.b, "O", "fewer than the 2");
  }
  {
    UlogBuilder u;
    u.msg('L', "\x01\x02");
    expect_input_error(u.b, "L", "fewer than the 9");
  }
  {
    UlogBuilder u;
    u.msg('B', std::string(40, '\0'));
    expect_input_error(u.b, "B", "first message");
  }
  {
    UlogBuilder u(1, false);
    std::string flags(40, '\0');
    flags[9] = 4;
    u.msg('B', flags);
    expect_input_error(u.b, "B incompat_flags", "at byte 28: incompatible flag bits 4 in byte 1");
  }
  {
    UlogBuilder u(1, false);
    std::string flags(40, '\0');
    flags[8] = 1;
    flags[16] = static_cast<char>(0xff);
    flags[17] = static_cast<char>(0xff);
    flags[18] = static_cast<char>(0xff);
    u.msg('B', flags);
    expect_input_error(u.b, "B appended_offsets", "16777215");
  }
  {
    UlogBuilder u;
    u.msg('B' + 20, "unknown type: skipped");  // 'V', not defined: skipped and counted
    EXPECT_EQ(parse_ulog(u.b, "x.ulg").summary.unknown_messages, 1u);
  }
}

TEST(Px4UlogBadInput, AttitudeTopicsAndFields) {
  {
    UlogBuilder u;  // no attitude, no GPS
    u.fmt("foo:uint64_t timestamp;");
    u.add(0, 1, "foo");
    expect_input_error(u.b, "A vehicle_gps_position", "neither");
  }
  {
    UlogBuilder u = attitude_log();
    expect_input_error(u.b, "D sensor_gps.time_utc_usec", "no usable GNSS time");
  }
  {
    UlogBuilder u = attitude_log();
    for (int i = 0; i < 5; ++i)
      u.data(4, gps_payload(1'000'000ULL * static_cast<std::uint64_t>(i + 1), 0, 1));
    expect_input_error(u.b, "D sensor_gps.time_utc_usec", "0 message(s)");
  }
  {
    UlogBuilder u;
    u.fmt("vehicle_attitude:uint64_t timestamp;float[3] q;");
    u.fmt("sensor_gps:uint64_t timestamp;uint64_t time_utc_usec;uint8_t fix_type;");
    u.add(0, 3, "vehicle_attitude");
    u.add(0, 4, "sensor_gps");
    for (int i = 0; i < 5; ++i) {
      const std::uint64_t t = 1'000'000ULL * static_cast<std::uint64_t>(i + 1);
      u.data(4, gps_payload(t, utc_us_of_boot(t), 3));
    }
    expect_input_error(u.b, "F vehicle_attitude.q", "field is float[3], expected float[4]");
  }
  {
    UlogBuilder u;
    u.fmt("vehicle_attitude:uint64_t timestamp;float[4] q;");
    u.fmt("sensor_gps:uint64_t timestamp;uint64_t time_utc_usec;");
    u.add(0, 3, "vehicle_attitude");
    u.add(0, 4, "sensor_gps");
    expect_input_error(u.b, "F sensor_gps.fix_type", "no field 'fix_type'");
  }
  {
    UlogBuilder u = attitude_log();
    for (int i = 0; i < 5; ++i) {
      const std::uint64_t t = 1'000'000ULL * static_cast<std::uint64_t>(i + 1);
      u.data(4, gps_payload(t, utc_us_of_boot(t), 3));
    }
    u.data(3, attitude_payload(1'000'000, {0, 0, 0}));
    expect_input_error(u.b, "D vehicle_attitude", "1 usable attitude samples");
  }
}

// Random damage to the real log: the reader must end in a result or a rangecal::Error, never a
// crash, another exception type or a hang.
TEST(Px4UlogBadInput, DamagedRealLogNeverCrashes) {
  const std::string full = test::read_text(sample("sample_log_small.ulg"));
  std::mt19937 rng(2024);
  std::size_t errors = 0, results = 0;
  for (int trial = 0; trial < 150; ++trial) {
    std::string b = full;
    const std::size_t region = trial % 3 == 0 ? 60'000 : b.size();  // definitions or anywhere
    for (int k = 0; k < 1 + trial % 20; ++k)
      b[std::uniform_int_distribution<std::size_t>(0, region - 1)(rng)] = static_cast<char>(rng());
    if (trial % 5 == 0) b.resize(std::uniform_int_distribution<std::size_t>(0, b.size())(rng));
    try {
      ulog_attitude(parse_ulog(b, "damaged.ulg"));
      ++results;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::input);
      ++errors;
    }
  }
  std::cout << "damaged logs: " << results << " read, " << errors << " rejected with an input error\n";
  EXPECT_GT(errors, 0u);
}

}  // namespace
}  // namespace rangecal
