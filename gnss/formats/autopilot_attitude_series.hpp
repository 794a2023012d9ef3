#pragma once
// The end both autopilot attitude readers share (PX4 ULog, ArduPilot DataFlash; docs/gnss.md
// "Autopilot attitude logs"): the log's valid attitude samples on its boot clock, in log order,
// become an AttitudeSeries on UTC through the report's boot-time fit. A sample not after the
// previous kept one is skipped and counted (interpolation needs strictly increasing times); at
// least two must be left to interpolate, or the error names the log's attitude messages and
// every count; the report takes the count kept and the UTC span.
#include <cstdint>
#include <string>
#include <vector>

#include "gnss/formats/autopilot_attitude_report.hpp"
#include "gnss/track/attitude.hpp"

namespace rangecal {

/// One valid attitude message of an autopilot log: its boot time (µs) and its attitude.
struct BootAttitudeSample {
  std::int64_t boot_us = 0;
  Attitude att;
};

/// How the error for too few samples names the log's attitude messages.
struct AutopilotAttitudeNames {
  std::string field;     ///< "ATT", "D vehicle_attitude"
  std::string messages;  ///< what `rep.attitude_messages` counts: "ATT messages", "messages"
  std::string invalid;   ///< what `rep.attitude_invalid` counts: "out of range or without a time"
};

/// The series of `samples` on UTC through `rep.fit`, `rep` completed (attitude_not_increasing,
/// attitude_samples, utc_start, utc_end) and copied to `*report` when given. Throws
/// rangecal::Error (kind input, file `path`, line 0, field `names.field`) when fewer than two
/// samples are left.
AttitudeSeries autopilot_attitude_series(const std::vector<BootAttitudeSample>& samples,
                                         const std::string& path, const AutopilotAttitudeNames& names,
                                         AutopilotAttitudeReport rep, AutopilotAttitudeReport* report);

}  // namespace rangecal
