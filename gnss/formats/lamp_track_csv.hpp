#pragma once
// `gnss/lamp_track.csv` (docs/outputs.md): `utc,E,N,U,sdE,sdN,sdU,quality` — utc ISO 8601 with 9 fraction
// digits (ns, so times survive a write/read round trip exactly), E/N/U and sds in metres with 4
// decimals (0.1 mm), quality the RTKLIB Q. The gnss stage writes it; the align stage reads it.
#include <string>

#include "gnss/track/lamp_track.hpp"

namespace rangecal {

/// The CSV text of a track (header line, then one line per epoch, LF endings).
std::string format_lamp_track_csv(const LampTrack& track);

/// Writes the track atomically (temp file + rename).
void write_lamp_track_csv(const std::string& path, const LampTrack& track);

/// Reads a lamp_track.csv. Velocity is not stored in the file, so vel_enu is NaN on every epoch.
/// Throws rangecal::Error (input) naming file, line and column for a missing file or column, a bad
/// time or number, a negative sd, a quality outside 1–6, times not strictly increasing, or no epochs.
LampTrack read_lamp_track_csv(const std::string& path);
/// As read_lamp_track_csv, from text in memory; `path` is for messages.
LampTrack parse_lamp_track_csv(const std::string& text, const std::string& path);

}  // namespace rangecal
