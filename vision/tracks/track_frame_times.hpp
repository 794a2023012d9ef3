#pragma once
// The times of an imported track's frames (docs/formats.md "Imported tracks"): from a `frame,utc` CSV
// (the frames timestamps CSV's form; a `file` column, if present, is not needed and ignored) or from a
// nominal start and rate, t = t0 + (frame − t0_frame)/fps. Either may be UTC (a camera with time
// code) or nominal (one without: pipeline/steps/camera_clock.hpp then finds the offset and rate).
#include <cstdint>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"
#include "vision/tracks/image_track.hpp"

namespace rangecal {

/// The time of each of track.points from the CSV `csv_path`. Throws rangecal::Error (input) naming the
/// CSV's line and field for a bad frame number or time, frames or times not strictly increasing, and
/// naming the track's line when one of its frames has no time in the CSV.
std::vector<UtcTime> track_times_from_csv(const ImageTrack& track, const std::string& csv_path);

/// The time of each of track.points at t0 + (frame − t0_frame)/fps (fps > 0, frames/s).
std::vector<UtcTime> track_times_from_rate(const ImageTrack& track, UtcTime t0, std::int64_t t0_frame,
                                           double fps);

}  // namespace rangecal
