// The one classifier of two UTC spans (gnss/time/span_comparison.hpp) used by `inspect` and by the
// align stage: overlap, and for disjoint spans a day or more (camera clock not set), GPS − UTC leap
// seconds (GPST vs UTC), whole hours (a time zone), or a plain gap — each at and just beyond its
// tolerance.
#include "gnss/time/span_comparison.hpp"

#include <gtest/gtest.h>

namespace rangecal {
namespace {

// 2026-05-14T02:30:00Z + seconds.
UtcTime at(double s) {
  return add_seconds(utc_from_civil(2026, 5, 14, 2, 30, 0, 0), s);
}
UtcSpan span(double first_s, double last_s) {
  return UtcSpan{at(first_s), at(last_s)};
}

TEST(SpanComparison, OverlapMeasuresTheCommonPart) {
  const SpanComparison c = compare_spans(span(0, 600), span(550, 700));
  EXPECT_EQ(c.relation, SpanRelation::overlap);
  EXPECT_DOUBLE_EQ(c.overlap_s, 50);
  EXPECT_DOUBLE_EQ(c.gap_s, 0);
  EXPECT_EQ(likely_cause(c), "");
  // A shared single instant is an overlap; one nanosecond apart is not.
  EXPECT_EQ(compare_spans(span(0, 10), span(10, 20)).relation, SpanRelation::overlap);
  const UtcSpan after{UtcTime{at(10).ns + 1}, at(20)};
  EXPECT_NE(compare_spans(span(0, 10), after).relation, SpanRelation::overlap);
}

TEST(SpanComparison, DaysApartIsACameraClockNotSet) {
  // Same flight, frames stamped one day late (the date was wrong).
  const SpanComparison c = compare_spans(span(0, 600), span(86400 + 5, 86400 + 595));
  EXPECT_EQ(c.relation, SpanRelation::clock_not_set);
  EXPECT_DOUBLE_EQ(c.gap_s, 86400 + 5 - 600);
  EXPECT_DOUBLE_EQ(c.cause_offset_s, 86400);
  EXPECT_EQ(likely_cause(c), "camera clock not set (date)");
  const std::string text = describe_span_comparison(c, "camera c1 frames", "the lamp track");
  EXPECT_NE(text.find("camera clock not set"), std::string::npos) << text;
  EXPECT_NE(text.find("about 1 day(s)"), std::string::npos) << text;
  // A clock left at its 1970 default: far earlier, still the clock.
  const UtcSpan epoch{UtcTime{0}, UtcTime{600 * kNsPerSecond}};
  const SpanComparison e = compare_spans(span(0, 600), epoch);
  EXPECT_EQ(e.relation, SpanRelation::clock_not_set);
  EXPECT_LT(e.gap_s, 0);
}

TEST(SpanComparison, LeapSecondsAreGpstVsUtcWithinHalfASecond) {
  // 2026: GPS − UTC = 18 s. A 10 s recording at the end of a 10 s track, stamped in GPST.
  for (double d : {18.0, 17.6, 18.4}) {
    const SpanComparison c = compare_spans(span(0, 10), span(d, d + 10));
    EXPECT_EQ(c.relation, SpanRelation::gpst_vs_utc) << d;
    EXPECT_EQ(c.leap_seconds, 18);
    EXPECT_DOUBLE_EQ(c.cause_offset_s, 18);
    EXPECT_EQ(likely_cause(c), "GPST vs UTC");
  }
  for (double d : {17.4, 18.6})
    EXPECT_EQ(compare_spans(span(0, 10), span(d, d + 10)).relation, SpanRelation::gap) << d;
  // The other way round (frames 18 s early).
  const SpanComparison r = compare_spans(span(0, 10), span(-18, -8));
  EXPECT_EQ(r.relation, SpanRelation::gpst_vs_utc);
  EXPECT_DOUBLE_EQ(r.cause_offset_s, -18);
  // A short recording near the end of a long track: any offset putting it back inside counts.
  const SpanComparison edge = compare_spans(span(0, 1200), span(1190 + 18, 1200 + 18));
  EXPECT_EQ(edge.relation, SpanRelation::gpst_vs_utc);
  // Before 2017 the table gives 17 s (2015-07-01 … 2016-12-31).
  const UtcTime t2016 = utc_from_civil(2016, 3, 1, 12, 0, 0, 0);
  const SpanComparison old = compare_spans(UtcSpan{t2016, add_seconds(t2016, 5)},
                                           UtcSpan{add_seconds(t2016, 17), add_seconds(t2016, 22)});
  EXPECT_EQ(old.leap_seconds, 17);
  EXPECT_EQ(old.relation, SpanRelation::gpst_vs_utc);
}

TEST(SpanComparison, WholeHoursAreATimeZoneWithinAMinute) {
  for (double d : {2 * 3600.0, 2 * 3600.0 + 59, 2 * 3600.0 - 59}) {
    const SpanComparison c = compare_spans(span(0, 600), span(d, d + 600));
    EXPECT_EQ(c.relation, SpanRelation::time_zone) << d;
    EXPECT_DOUBLE_EQ(c.cause_offset_s, 7200);
    EXPECT_EQ(likely_cause(c), "a time zone");
    const std::string text = describe_span_comparison(c, "camera c1 frames", "the lamp track");
    EXPECT_NE(text.find("UTC+2"), std::string::npos) << text;
  }
  EXPECT_EQ(compare_spans(span(0, 600), span(7200 + 61, 7800 + 61)).relation, SpanRelation::gap);
  // West of Greenwich: frames 5 h early.
  const SpanComparison w = compare_spans(span(0, 600), span(-5 * 3600.0, -5 * 3600.0 + 600));
  EXPECT_EQ(w.relation, SpanRelation::time_zone);
  EXPECT_DOUBLE_EQ(w.cause_offset_s, -18000);
  // A camera that recorded 10 s in the middle of a 20 min flight, its clock an hour ahead.
  EXPECT_EQ(compare_spans(span(0, 1200), span(3600 + 300, 3600 + 310)).relation, SpanRelation::time_zone);
}

TEST(SpanComparison, AnythingElseIsAPlainGap) {
  const SpanComparison c = compare_spans(span(0, 60), span(130, 190));  // 70 s later, same length
  EXPECT_EQ(c.relation, SpanRelation::gap);
  EXPECT_DOUBLE_EQ(c.gap_s, 70);
  EXPECT_DOUBLE_EQ(c.offset_min_s, 130);
  EXPECT_DOUBLE_EQ(c.offset_max_s, 130);
  EXPECT_EQ(likely_cause(c), "");
  const std::string text = describe_span_comparison(c, "b", "a");
  EXPECT_NE(text.find("a gap of 70.000 s"), std::string::npos) << text;
  // 15 h: beyond any time zone, short of a day.
  EXPECT_EQ(compare_spans(span(0, 60), span(15 * 3600.0, 15 * 3600.0 + 60)).relation, SpanRelation::gap);
}

}  // namespace
}  // namespace rangecal
