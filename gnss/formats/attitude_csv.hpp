#pragma once
// Reader of the hand-made attitude CSV `utc,roll_deg,pitch_deg,yaw_deg` (docs/formats.md): utc ISO 8601
// with `Z` (up to 9 fraction digits), angles in degrees in the conventions of
// gnss/track/attitude.hpp (body FRD → NED, yaw clockwise from north, 0–360 yaw accepted).
// Autopilot logs (PX4 ULog, ArduPilot DataFlash) are read by their own readers;
// gnss/formats/attitude_file.hpp chooses among them by the file's content.
#include <string>

#include "gnss/track/attitude.hpp"

namespace rangecal {

/// Reads the attitude CSV. Throws rangecal::Error (input) naming file, line and column for a
/// missing file or column, a bad time or number, an angle out of range (roll [-180, 180], pitch
/// [-90, 90], yaw [-360, 360]), times not strictly increasing, or fewer than 2 samples.
AttitudeSeries read_attitude_csv(const std::string& path);
/// As read_attitude_csv, from text in memory; `path` is for messages.
AttitudeSeries parse_attitude_csv(const std::string& text, const std::string& path);

}  // namespace rangecal
