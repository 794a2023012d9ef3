#include "gnss/time/utc_time.hpp"

#include <gtest/gtest.h>

namespace rangecal {
namespace {

TEST(UtcTime, Iso8601RoundTripKeepsNanoseconds) {
  const auto t = parse_iso8601_utc("2018-10-09T12:21:53.123456789Z");
  ASSERT_TRUE(t);
  EXPECT_EQ(format_iso8601_utc(*t), "2018-10-09T12:21:53.123456789Z");
  EXPECT_EQ(format_iso8601_utc(*t, 3), "2018-10-09T12:21:53.123Z");
  EXPECT_EQ(format_iso8601_utc(*t, 0), "2018-10-09T12:21:53Z");
  // 1539087713 s is 2018-10-09T12:21:53Z (date -u -d @1539087713).
  EXPECT_EQ(t->ns, 1539087713LL * kNsPerSecond + 123456789);
}

TEST(UtcTime, Iso8601ShortFractionAndNegativeEpoch) {
  EXPECT_EQ(parse_iso8601_utc("1970-01-01T00:00:00.5Z")->ns, 500000000);
  // Years before 1970 or after 2200 are outside the supported span (docs/reliability.md).
  std::string why;
  EXPECT_FALSE(parse_iso8601_utc("1969-12-31T23:59:59Z", &why));
  EXPECT_NE(why.find("1970-2200"), std::string::npos) << why;
  EXPECT_FALSE(parse_iso8601_utc("2263-01-01T00:00:00Z"));
  EXPECT_TRUE(parse_iso8601_utc("2200-12-31T23:59:59.999999999Z"));
  EXPECT_EQ(format_iso8601_utc(UtcTime{-1}), "1969-12-31T23:59:59.999999999Z");
}

TEST(UtcTime, Iso8601RejectsBadText) {
  std::string why;
  EXPECT_FALSE(parse_iso8601_utc("2018-10-09T12:21:53", &why));
  EXPECT_NE(why.find("Z"), std::string::npos);
  EXPECT_FALSE(parse_iso8601_utc("2018-02-30T00:00:00Z", &why));
  EXPECT_FALSE(parse_iso8601_utc("2018-10-09T24:00:00Z", &why));
  // Years outside 1970-2200 would overflow int64 ns arithmetic (found by fuzzing).
  EXPECT_FALSE(parse_iso8601_utc("0219-10-09T12:00:00Z", &why));
  EXPECT_NE(why.find("1970-2200"), std::string::npos) << why;
  EXPECT_FALSE(parse_iso8601_utc("9999-12-31T23:59:59Z", &why));
  EXPECT_TRUE(parse_iso8601_utc("1970-01-01T00:00:00Z", &why));
  EXPECT_TRUE(parse_iso8601_utc("2200-12-31T23:59:59.999999999Z", &why));
  EXPECT_FALSE(parse_iso8601_utc("2018-10-09T12:21:53.1234567891Z", &why));
  EXPECT_FALSE(parse_iso8601_utc("2018-10-09T12:21:53.Z", &why));
  EXPECT_FALSE(parse_iso8601_utc("garbage", &why));
}

TEST(UtcTime, LeapSecondTable) {
  // GPS−UTC: 0 at the GPS epoch, 13 in 2005, 18 since 2017-01-01 (IERS Bulletin C).
  EXPECT_EQ(gps_minus_utc_seconds_at_utc(utc_from_civil(1980, 1, 6, 0, 0, 0, 0)), 0);
  EXPECT_EQ(gps_minus_utc_seconds_at_utc(utc_from_civil(2005, 6, 1, 0, 0, 0, 0)), 13);
  EXPECT_EQ(gps_minus_utc_seconds_at_utc(utc_from_civil(2016, 12, 31, 23, 59, 59, 0)), 17);
  EXPECT_EQ(gps_minus_utc_seconds_at_utc(utc_from_civil(2017, 1, 1, 0, 0, 0, 0)), 18);
  EXPECT_EQ(gps_minus_utc_seconds_at_utc(utc_from_civil(2026, 11, 23, 0, 0, 0, 0)), 18);
}

TEST(UtcTime, GpsToUtcMatchesRtklibSample) {
  // From tests/data/external/gnss/SOURCE.md: 12:22:11.000 GPST = 12:21:53.000 UTC = week 2022 TOW 217331.
  const GpsTime g = gps_from_week_tow(2022, *parse_decimal_seconds_ns("217331.000"));
  EXPECT_EQ(g, gps_from_civil(2018, 10, 9, 12, 22, 11, 0));
  EXPECT_EQ(format_iso8601_utc(gps_to_utc(g), 3), "2018-10-09T12:21:53.000Z");
  EXPECT_EQ(utc_to_gps(gps_to_utc(g)), g);
}

TEST(UtcTime, GpsUtcRoundTripAcrossLeapSeconds) {
  for (int y = 1981; y <= 2026; ++y) {
    for (int mo : {1, 6, 7, 12}) {
      const UtcTime u = utc_from_civil(y, mo, 1, 0, 0, 0, 123);
      EXPECT_EQ(gps_to_utc(utc_to_gps(u)), u) << y << "-" << mo;
    }
  }
  // The second just before and after the 2016-12-31 leap second.
  const UtcTime before = utc_from_civil(2016, 12, 31, 23, 59, 59, 0);
  const UtcTime after = utc_from_civil(2017, 1, 1, 0, 0, 0, 0);
  EXPECT_EQ(utc_to_gps(after).ns - utc_to_gps(before).ns, 2 * kNsPerSecond);  // the leap second between
}

TEST(UtcTime, DecimalSecondsAreExact) {
  EXPECT_EQ(*parse_decimal_seconds_ns("217331.000"), 217331 * kNsPerSecond);
  EXPECT_EQ(*parse_decimal_seconds_ns("0.000000001"), 1);
  EXPECT_EQ(*parse_decimal_seconds_ns("-1.5"), -1500000000);
  EXPECT_FALSE(parse_decimal_seconds_ns("1.2.3"));
  EXPECT_FALSE(parse_decimal_seconds_ns("1e3"));
  EXPECT_FALSE(parse_decimal_seconds_ns(""));
  EXPECT_FALSE(parse_decimal_seconds_ns("0.0000000001"));
  // Found by fuzz_rtklib_pos (UBSan: signed overflow): whole seconds whose ns overflow an int64.
  EXPECT_EQ(*parse_decimal_seconds_ns("9223372035.999999999"), 9223372035999999999);
  EXPECT_FALSE(parse_decimal_seconds_ns("9223372036"));
  EXPECT_FALSE(parse_decimal_seconds_ns("21733217331.0"));
  EXPECT_FALSE(parse_decimal_seconds_ns("-999999999999"));
}

}  // namespace
}  // namespace rangecal
