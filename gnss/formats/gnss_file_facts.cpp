#include "gnss/formats/gnss_file_facts.hpp"

#include <map>
#include <sstream>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "config/text_encoding.hpp"
#include "gnss/formats/ardupilot_dataflash.hpp"
#include "gnss/formats/attitude_csv.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "gnss/formats/pole_survey_csv.hpp"
#include "gnss/formats/px4_ulog.hpp"
#include "gnss/formats/rtklib_pos_reader.hpp"

namespace rangecal {

namespace {

// "epochs Q=1 (fix)" … for the qualities present, in Q order; a note when most are not fixed.
void add_quality_counts(FileFacts* f, const std::map<int, std::uint64_t>& by_q, std::uint64_t total) {
  for (const auto& [q, n] : by_q)
    f->counts.emplace_back("epochs Q=" + std::to_string(q) + " (" + rtklib_quality_name(q) + ")", n);
  const auto fix = by_q.count(1) ? by_q.at(1) : 0;
  if (total > 0 && fix * 2 < total)
    f->notes.push_back(std::to_string(total - fix) + " of " + std::to_string(total) +
                       " epochs are not fixed (Q > 1); the gnss stage keeps only the Q values in "
                       "gnss.accept_quality");
}

// Intervals longer than 1.5 nominal intervals: the gaps a reader of the file should know about.
std::uint64_t count_gaps(const std::vector<UtcTime>& t, std::optional<double> rate_hz) {
  if (!rate_hz || t.size() < 2) return 0;
  const double limit = 1.5 / *rate_hz;
  std::uint64_t n = 0;
  for (std::size_t i = 1; i < t.size(); ++i)
    if (seconds_between(t[i - 1], t[i]) > limit) ++n;
  return n;
}

void set_series(FileFacts* f, const std::vector<UtcTime>& t) {
  if (t.empty()) return;
  f->utc = UtcSpan{t.front(), t.back()};
  f->rate_hz = median_rate_hz(t);
  if (f->rate_hz) f->rate_source = "median interval";
}

std::string pos_time_system(const PosHeader& h, UtcTime first) {
  const std::string format =
      h.time_format == PosTimeFormat::week_tow ? "GPS week + seconds of week" : "calendar";
  switch (h.time_system) {
    case PosTimeSystem::gpst:
      return "GPST (column header, " + format + "); UTC = GPST - " +
             std::to_string(gps_minus_utc_seconds_at_utc(first)) + " s (leap seconds)";
    case PosTimeSystem::utc:
      return "UTC (column header, " + format + ")";
    case PosTimeSystem::jst:
      return "JST (column header, " + format + "); UTC = JST - 9 h";
  }
  return "";
}

// The `% key : value` header lines a user recognises from RTKLIB, as written.
void add_pos_header_lines(FileFacts* f, const std::string& text) {
  std::istringstream in{std::string(strip_utf8_bom(text))};
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] != '%') break;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string key{trim(std::string_view(line).substr(1, colon - 1))};
    if (key == "obs start" || key == "obs end" || key == "pos mode" || key == "solution")
      f->details.emplace_back(key,
                              printable_text(std::string(trim(std::string_view(line).substr(colon + 1)))));
  }
}

std::string boot_fit_text(const AutopilotAttitudeReport& r) {
  return "boot time (us since boot); UTC from " + r.gps_message + " (" + std::to_string(r.fit.used) + " of " +
         std::to_string(r.fit.pairs) + " GNSS fixes, residual rms " +
         format_number("%.0f", r.fit.residual_rms_us) + " us, max " +
         format_number("%.0f", r.fit.residual_max_us) + " us" +
         (r.fit.drift_fitted ? ", drift " + format_number("%.2f", r.fit.drift_ppm) + " ppm" : "") + ")";
}

void add_attitude_report(FileFacts* f, const AutopilotAttitudeReport& r, const AttitudeSeries& s) {
  f->time_system = boot_fit_text(r);
  std::vector<UtcTime> t;
  t.reserve(s.samples.size());
  for (const auto& a : s.samples) t.push_back(a.utc);
  set_series(f, t);
  f->counts.emplace_back("attitude samples (" + r.attitude_message + ")", r.attitude_samples);
  f->counts.emplace_back("GNSS messages (" + r.gps_message + ")", r.gps_messages);
  if (r.gps_skipped > 0) f->counts.emplace_back("GNSS messages without fix or time", r.gps_skipped);
}

/// The one note of a log cut off mid-message (from the walk over the whole file, which is there
/// whether or not the attitude could be put on UTC).
void add_truncation_note(FileFacts* f, std::uint64_t truncated_bytes) {
  if (truncated_bytes > 0)
    f->notes.push_back(std::to_string(truncated_bytes) + " bytes of an incomplete last message not read");
}

}  // namespace

FileFacts pos_file_facts(const std::string& path) {
  const std::string text = read_file_text(path);
  const PosFile pos = parse_rtklib_pos(text, path);
  FileFacts f;
  f.path = path;
  f.kind = "RTKLIB .pos";
  f.size_bytes = text.size();
  std::vector<UtcTime> t;
  std::map<int, std::uint64_t> by_q;
  for (const PosEpoch& e : pos.epochs) {
    t.push_back(e.utc);
    ++by_q[e.quality];
  }
  set_series(&f, t);
  f.time_system = pos_time_system(pos.header, pos.epochs.front().utc);
  f.counts.emplace_back("epochs", pos.epochs.size());
  add_quality_counts(&f, by_q, pos.epochs.size());
  f.counts.emplace_back("gaps > 1.5 intervals", count_gaps(t, f.rate_hz));
  if (!pos.header.program.empty()) f.details.emplace_back("program", pos.header.program);
  add_pos_header_lines(&f, text);
  f.details.emplace_back("position", to_string(pos.header.position_format));
  f.details.emplace_back("velocity columns", pos.header.has_velocity ? "yes" : "no");
  f.details.emplace_back("ref pos", pos.header.ref_pos_ecef ? "yes" : "none");
  return f;
}

FileFacts ulog_file_facts(const std::string& path) {
  const UlogLog log = read_ulog(path);
  const UlogSummary& s = log.summary;
  FileFacts f;
  f.path = path;
  f.kind = "PX4 ULog";
  f.size_bytes = s.file_bytes;
  f.details.emplace_back("ULog version", std::to_string(s.version));
  for (const char* key : {"sys_name", "ver_hw", "ver_sw"})
    if (const auto v = s.info_value(key)) f.details.emplace_back(key, *v);
  if (s.first_timestamp_us && s.last_timestamp_us)
    f.details.emplace_back("boot time span", format_number("%.6f", *s.first_timestamp_us * 1e-6) + " .. " +
                                                 format_number("%.6f", *s.last_timestamp_us * 1e-6) + " s");
  try {
    AutopilotAttitudeReport r;
    const AttitudeSeries a = ulog_attitude(log, &r);
    add_attitude_report(&f, r, a);
  } catch (const Error& e) {
    f.time_system = "boot time (us since boot); no UTC";
    f.notes.push_back("no attitude on UTC: " + e.reason());
  }
  std::uint64_t data = 0;
  for (const UlogTopicCount& t : s.topics) data += t.messages;
  f.counts.emplace_back("data messages", data);
  for (const UlogTopicCount& t : s.topics)
    f.counts.emplace_back("messages " + t.topic + (t.multi_id ? "[" + std::to_string(t.multi_id) + "]" : ""),
                          t.messages);
  f.counts.emplace_back("logged strings", s.logged_strings);
  f.counts.emplace_back("parameters", s.parameters);
  if (s.dropouts > 0) f.counts.emplace_back("dropouts", s.dropouts);
  add_truncation_note(&f, s.truncated_bytes);
  return f;
}

FileFacts dataflash_file_facts(const std::string& path) {
  const std::string bytes = read_file_text(path);
  const DataflashSummary s = walk_dataflash(bytes, path, [](const DataflashFormat&, std::string_view) {});
  FileFacts f;
  f.path = path;
  f.kind = "ArduPilot DataFlash";
  f.size_bytes = bytes.size();
  try {
    AutopilotAttitudeReport r;
    const AttitudeSeries a = dataflash_attitude(bytes, path, &r);
    add_attitude_report(&f, r, a);
    f.time_system += "; GPS week + ms of week -> UTC with " +
                     std::to_string(f.utc ? gps_minus_utc_seconds_at_utc(f.utc->first) : 0) + " leap seconds";
  } catch (const Error& e) {
    f.time_system = "boot time (us since boot); no UTC";
    f.notes.push_back("no attitude on UTC: " + e.reason());
  }
  f.counts.emplace_back("messages", s.messages);
  for (const DataflashFormat& d : s.formats)
    if (d.messages > 0) f.counts.emplace_back("messages " + d.name, d.messages);
  f.counts.emplace_back("message types defined", s.formats.size());
  add_truncation_note(&f, s.truncated_bytes);
  return f;
}

namespace {

/// The facts every UTC-stamped CSV of ours shares: kind, size, time system, span and rate of `t`.
FileFacts utc_csv_facts(const std::string& path, const char* kind, const std::string& text,
                        const std::vector<UtcTime>& t) {
  FileFacts f;
  f.path = path;
  f.kind = kind;
  f.size_bytes = text.size();
  f.time_system = "UTC (ISO 8601 with Z)";
  set_series(&f, t);
  return f;
}

}  // namespace

FileFacts attitude_csv_file_facts(const std::string& path) {
  const std::string text = read_file_text(path);
  const AttitudeSeries a = parse_attitude_csv(text, path);
  std::vector<UtcTime> t;
  for (const auto& s : a.samples) t.push_back(s.utc);
  FileFacts f = utc_csv_facts(path, "attitude CSV", text, t);
  f.counts.emplace_back("samples", a.samples.size());
  return f;
}

FileFacts lamp_track_file_facts(const std::string& path) {
  const std::string text = read_file_text(path);
  const LampTrack track = parse_lamp_track_csv(text, path);
  std::vector<UtcTime> t;
  std::map<int, std::uint64_t> by_q;
  for (const auto& e : track.epochs) {
    t.push_back(e.utc);
    ++by_q[e.quality];
  }
  FileFacts f = utc_csv_facts(path, "lamp track CSV", text, t);
  f.counts.emplace_back("epochs", track.epochs.size());
  add_quality_counts(&f, by_q, track.epochs.size());
  f.counts.emplace_back("gaps > 1.5 intervals", count_gaps(t, f.rate_hz));
  return f;
}

FileFacts pole_survey_file_facts(const std::string& path) {
  const std::string text = read_file_text(path);
  const CsvTable table = parse_csv(text, path);
  const bool geodetic = table.find_column("lat").has_value();
  // Geodetic rows are converted about an origin; the first pole serves, as inspect shows no ENU.
  GeodeticOrigin origin;
  if (geodetic && !table.records.empty()) {
    const CsvRecord& r = table.records.front();
    origin = {table.number_in(r, table.column("lat"), -90, 90, "latitude, degrees"),
              table.number_in(r, table.column("lon"), -180, 180, "longitude, degrees"),
              table.number(r, table.column("h"))};
  }
  const auto poles = parse_pole_survey(text, path, origin);
  FileFacts f;
  f.path = path;
  f.kind = "pole survey CSV";
  f.size_bytes = text.size();
  std::uint64_t control = 0;
  for (const auto& p : poles) control += p.role == PoleRole::control;
  f.counts.emplace_back("poles", poles.size());
  f.counts.emplace_back("control poles", control);
  f.counts.emplace_back("check poles", poles.size() - control);
  f.details.emplace_back("coordinates",
                         geodetic ? "WGS84 lat, lon (deg), ellipsoidal h (m)" : "site ENU (m)");
  return f;
}

FileFacts pole_picks_file_facts(const std::string& path) {
  const std::string text = read_file_text(path);
  const auto picks = parse_pole_picks(text, path, ImageExtent{});
  FileFacts f;
  f.path = path;
  f.kind = "pole picks CSV";
  f.size_bytes = text.size();
  f.counts.emplace_back("picks", picks.size());
  return f;
}

}  // namespace rangecal
