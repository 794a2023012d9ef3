#pragma once
// Two UTC time spans side by side — a lamp track and a camera's frames, an attitude log and a .pos —
// and, when they do not overlap, the likely cause (docs/alignment.md "When nothing aligns"). Used
// by `rangecal inspect` (overlap of the files given) and by the align stage (its error when no
// frame aligns), so both say the same thing.
//
// The clock offset d that would explain the two spans is not one number when their lengths differ:
// every d that puts the shorter span, moved by −d, inside the longer one explains them equally
// well. With s = other.first − reference.first and e = other.last − reference.last, that set is
// the interval [min(s, e), max(s, e)] (a point, s = e, for spans of equal length). A cause is
// named when its offset lies in that interval, widened by the cause's tolerance:
//   - GPST vs UTC:  d = ±(GPS − UTC) at the reference's start (18 s since 2017; leap-second table,
//                   utc_time.hpp), ±0.5 s — stamps in GPS time taken for UTC, or the reverse;
//   - a time zone:  d = n hours, 1 ≤ |n| ≤ 14 (the zones span UTC−12 … UTC+14), ±1 min — a clock
//                   on local time;
//   - camera clock not set (date): |d| reaches a whole day or more (1 day − 1 min) — a clock never
//                   set, or set to the wrong date;
// checked in this order; otherwise the gap is reported as it is. Spans that share any instant
// overlap, and no cause is sought.
#include <string>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

/// First and last time stamp of a file or a series (first ≤ last).
struct UtcSpan {
  UtcTime first, last;
  double duration_s() const { return seconds_between(first, last); }
};

/// "2018-10-09T12:21:53.000Z .. 2018-10-09T12:56:24.000Z (2071.000 s)".
std::string format_utc_span(const UtcSpan& span);

enum class SpanRelation {
  overlap,        ///< the spans share at least one instant
  clock_not_set,  ///< a day or more apart: camera clock not set (date)
  gpst_vs_utc,    ///< apart by GPS − UTC (leap seconds)
  time_zone,      ///< apart by whole hours
  gap,            ///< apart by something else
};
const char* to_string(SpanRelation r);

struct SpanComparison {
  SpanRelation relation = SpanRelation::overlap;
  /// Length of the common part (s) when the spans overlap; 0 otherwise.
  double overlap_s = 0;
  /// Signed gap (s) when they do not overlap: other.first − reference.last when `other` is later
  /// (> 0), other.last − reference.first when earlier (< 0); 0 when they overlap.
  double gap_s = 0;
  /// The interval of clock offsets other − reference (s) that would put the shorter span inside
  /// the longer (header comment): [min(s, e), max(s, e)].
  double offset_min_s = 0, offset_max_s = 0;
  /// The offset the named cause stands for (s, other − reference): ±leap seconds, n·3600, or the
  /// middle of the offset interval rounded to whole days; the middle of the interval otherwise.
  double cause_offset_s = 0;
  int leap_seconds = 0;  ///< GPS − UTC (s) at the reference's start
};

/// Compares `other` with `reference` as described at the top of this file.
SpanComparison compare_spans(const UtcSpan& reference, const UtcSpan& other);

/// The likely cause in words ("camera clock not set (date)", "GPST vs UTC", "a time zone"); empty
/// for overlap and a plain gap.
std::string likely_cause(const SpanComparison& c);

/// One line for people: "overlap of 62.000 s (01 min 02 s) between …", or "no overlap: a gap of …
/// from the end of … to the start of …; likely cause: camera clock not set (date): an offset of
/// about 1 day(s) (… later)". `other_name` and `reference_name` name the two ("camera c1 frames",
/// "the lamp track").
std::string describe_span_comparison(const SpanComparison& c, const std::string& other_name,
                                     const std::string& reference_name);

}  // namespace rangecal
