#include "vision/tracks/track_frame_times.hpp"

#include <cmath>
#include <unordered_map>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "gnss/time/csv_utc.hpp"

namespace rangecal {

std::vector<UtcTime> track_times_from_csv(const ImageTrack& track, const std::string& csv_path) {
  const CsvTable t = read_csv(csv_path);
  const std::size_t c_frame = t.column("frame"), c_utc = t.column("utc");
  std::unordered_map<std::int64_t, UtcTime> time_of;
  time_of.reserve(t.records.size());
  const CsvRecord* previous = nullptr;
  std::int64_t previous_frame = 0;
  UtcTime previous_utc;
  for (const CsvRecord& r : t.records) {
    const std::int64_t frame = t.integer(r, c_frame);
    if (frame < 0)
      throw_input_error(csv_path, r.line, "frame", "negative frame number " + std::to_string(frame));
    const UtcTime utc = csv_utc(t, r, c_utc);
    if (previous && frame <= previous_frame)
      throw_input_error(csv_path, r.line, "frame",
                        "frame " + std::to_string(frame) + " is not after line " +
                            std::to_string(previous->line) + "'s frame " + std::to_string(previous_frame));
    if (previous && utc <= previous_utc)
      throw_input_error(csv_path, r.line, "utc",
                        "time " + format_iso8601_utc(utc) + " is not after line " +
                            std::to_string(previous->line) + "'s " + format_iso8601_utc(previous_utc) +
                            " (frames must be in time order)");
    time_of.emplace(frame, utc);
    previous = &r;
    previous_frame = frame;
    previous_utc = utc;
  }
  std::vector<UtcTime> out;
  out.reserve(track.points.size());
  for (const TrackedPoint& p : track.points) {
    const auto it = time_of.find(p.frame);
    if (it == time_of.end())
      throw_input_error(track.path, p.line, "frame",
                        "frame " + std::to_string(p.frame) + " has no time in " + csv_path);
    out.push_back(it->second);
  }
  return out;
}

std::vector<UtcTime> track_times_from_rate(const ImageTrack& track, UtcTime t0, std::int64_t t0_frame,
                                           double fps) {
  std::vector<UtcTime> out;
  out.reserve(track.points.size());
  for (const TrackedPoint& p : track.points)
    out.push_back(UtcTime{t0.ns + std::llround(1e9 * static_cast<double>(p.frame - t0_frame) / fps)});
  return out;
}

}  // namespace rangecal
