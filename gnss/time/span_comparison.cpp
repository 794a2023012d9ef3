#include "gnss/time/span_comparison.hpp"

#include <algorithm>
#include <cmath>

#include "config/number_format.hpp"

namespace rangecal {

namespace {

constexpr double kDay_s = 86400;
constexpr double kHour_s = 3600;
constexpr double kLeapTolerance_s = 0.5;
constexpr double kZoneTolerance_s = 60;
constexpr int kMaxZoneHours = 14;  // zones span UTC−12 … UTC+14

bool within(double d, double lo, double hi, double tolerance) {
  return d >= lo - tolerance && d <= hi + tolerance;
}

// "3725.000 s (1 h 02 min 05 s)": seconds for the exact value, days/hours for a reader.
std::string format_interval(double s) {
  std::string text = format_number("%.3f", s) + " s";
  const double a = std::fabs(s);
  if (a < 60) return text;
  const auto whole = static_cast<long long>(std::llround(a));
  const long long days = whole / 86400, hours = (whole % 86400) / 3600, minutes = (whole % 3600) / 60,
                  seconds = whole % 60;
  std::string human;
  if (days > 0) human = std::to_string(days) + " d ";
  if (days > 0 || hours > 0) human += std::to_string(hours) + " h ";
  human += format_number("%02.0f", static_cast<double>(minutes)) + " min " +
           format_number("%02.0f", static_cast<double>(seconds)) + " s";
  return text + " (" + human + ")";
}

}  // namespace

std::string format_utc_span(const UtcSpan& span) {
  return format_iso8601_utc(span.first, 3) + " .. " + format_iso8601_utc(span.last, 3) + " (" +
         format_interval(span.duration_s()) + ")";
}

const char* to_string(SpanRelation r) {
  switch (r) {
    case SpanRelation::overlap:
      return "overlap";
    case SpanRelation::clock_not_set:
      return "clock_not_set";
    case SpanRelation::gpst_vs_utc:
      return "gpst_vs_utc";
    case SpanRelation::time_zone:
      return "time_zone";
    case SpanRelation::gap:
      return "gap";
  }
  return "gap";
}

SpanComparison compare_spans(const UtcSpan& reference, const UtcSpan& other) {
  SpanComparison c;
  const double s = seconds_between(reference.first, other.first);
  const double e = seconds_between(reference.last, other.last);
  c.offset_min_s = std::min(s, e);
  c.offset_max_s = std::max(s, e);
  c.cause_offset_s = 0.5 * (c.offset_min_s + c.offset_max_s);
  c.leap_seconds = gps_minus_utc_seconds_at_utc(reference.first);
  if (other.first <= reference.last && reference.first <= other.last) {
    c.relation = SpanRelation::overlap;
    c.overlap_s =
        seconds_between(std::max(reference.first, other.first), std::min(reference.last, other.last));
    return c;
  }
  c.gap_s = other.first > reference.last ? seconds_between(reference.last, other.first)
                                         : -seconds_between(other.last, reference.first);
  const double sign = c.gap_s > 0 ? 1 : -1;  // a cause's offset has the gap's direction
  if (c.leap_seconds != 0 &&
      within(sign * c.leap_seconds, c.offset_min_s, c.offset_max_s, kLeapTolerance_s)) {
    c.relation = SpanRelation::gpst_vs_utc;
    c.cause_offset_s = sign * c.leap_seconds;
    return c;
  }
  for (int n = 1; n <= kMaxZoneHours; ++n) {
    if (within(sign * n * kHour_s, c.offset_min_s, c.offset_max_s, kZoneTolerance_s)) {
      c.relation = SpanRelation::time_zone;
      c.cause_offset_s = sign * n * kHour_s;
      return c;
    }
  }
  if (std::max(std::fabs(c.offset_min_s), std::fabs(c.offset_max_s)) >= kDay_s - kZoneTolerance_s) {
    c.relation = SpanRelation::clock_not_set;
    const double days = std::max(1.0, std::round(std::fabs(c.cause_offset_s) / kDay_s));
    c.cause_offset_s = sign * days * kDay_s;
    return c;
  }
  c.relation = SpanRelation::gap;
  return c;
}

std::string likely_cause(const SpanComparison& c) {
  switch (c.relation) {
    case SpanRelation::clock_not_set:
      return "camera clock not set (date)";
    case SpanRelation::gpst_vs_utc:
      return "GPST vs UTC";
    case SpanRelation::time_zone:
      return "a time zone";
    case SpanRelation::overlap:
    case SpanRelation::gap:
      return "";
  }
  return "";
}

std::string describe_span_comparison(const SpanComparison& c, const std::string& other_name,
                                     const std::string& reference_name) {
  if (c.relation == SpanRelation::overlap)
    return "overlap of " + format_interval(c.overlap_s) + " between " + other_name + " and " + reference_name;
  const bool later = c.gap_s > 0;
  std::string text = "no overlap: a gap of " + format_interval(std::fabs(c.gap_s)) + " from the end of " +
                     (later ? reference_name : other_name) + " to the start of " +
                     (later ? other_name : reference_name);
  const double shift = std::fabs(c.cause_offset_s);
  const std::string whose = " (" + other_name + (later ? " later)" : " earlier)");
  switch (c.relation) {
    case SpanRelation::clock_not_set:
      text += "; likely cause: " + likely_cause(c) + ": an offset of about " +
              format_number("%.0f", shift / kDay_s) + " day(s)" + whose;
      break;
    case SpanRelation::gpst_vs_utc:
      text += "; likely cause: " + likely_cause(c) + ": an offset of " + format_number("%.0f", shift) +
              " s, the GPS - UTC leap seconds" + whose + ", " +
              (later ? "GPS time written as UTC" : "UTC taken for GPS time");
      break;
    case SpanRelation::time_zone:
      text += "; likely cause: " + likely_cause(c) + ": an offset of " +
              format_number("%.0f", shift / kHour_s) + " h" + whose + ", a clock on local time (UTC" +
              (later ? "+" : "-") + format_number("%.0f", shift / kHour_s) + ")";
      break;
    case SpanRelation::gap:
    case SpanRelation::overlap:
      text += " (no clock offset of whole days, whole hours or leap seconds explains it)";
      break;
  }
  return text;
}

}  // namespace rangecal
