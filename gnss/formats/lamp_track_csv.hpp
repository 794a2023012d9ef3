#pragma once
// `gnss/lamp_track.csv` (docs/gnss.md): `utc,E,N,U,sdE,sdN,sdU,quality,rEN,rEU,rNU` — utc ISO 8601
// with 9 fraction digits (ns, so times survive a write/read round trip exactly), E/N/U and sds in
// metres with 4 decimals (0.1 mm), quality the RTKLIB Q, and the correlation coefficients of the
// ENU covariance (4 decimals; empty when not known), so the full 3×3 PPK covariance reaches the
// network bundle. The gnss stage writes it; the align and calibrate stages read it.
#include <string>

#include "gnss/track/lamp_track.hpp"

namespace rangecal {

/// The CSV text of a track (header line, then one line per epoch, LF endings).
std::string format_lamp_track_csv(const LampTrack& track);

/// Writes the track atomically (temp file + rename).
void write_lamp_track_csv(const std::string& path, const LampTrack& track);

/// Reads a lamp_track.csv. Velocity is not stored in the file, so vel_enu is NaN on every epoch;
/// cov_enu is D·R·D from the sd and the correlations, NaN when they are empty or the columns absent.
/// Throws rangecal::Error (input) naming file, line and column for a missing file or column, a bad
/// time or number, a negative sd, a quality outside 1–6, a correlation outside [−1, 1] or three
/// that no covariance has, times not strictly increasing, or no epochs.
LampTrack read_lamp_track_csv(const std::string& path);
/// As read_lamp_track_csv, from text in memory; `path` is for messages.
LampTrack parse_lamp_track_csv(const std::string& text, const std::string& path);

}  // namespace rangecal
