#pragma once
// What reading the attitude from an autopilot log found (PX4 ULog, ArduPilot DataFlash): the
// topics and time fields used, how many messages were kept or skipped and why, and the boot-time
// → UTC fit (gnss/time/boot_time_fit.hpp) with its residuals. The gnss stage writes it to run.json
// (counts.attitude); an `inspect` command can print it.
#include <cstddef>
#include <cstdint>
#include <string>

#include "gnss/time/boot_time_fit.hpp"
#include "gnss/time/utc_time.hpp"

namespace rangecal {

/// The GNSS receiver lag taken when a log does not say otherwise (ms; docs/gnss.md "Receiver
/// lag"): the time from a fix's instant to the autopilot's stamp of its message.
///  - ArduPilot DataFlash: 120 ms, what ArduPilot's u-blox driver assumes for M8-class receivers
///    (AP_GPS_UBLOX get_lag; 220 ms for older ones; GPS_DELAY_MS overrides it on the vehicle).
///  - PX4 ULog: 110 ms, PX4's default GPS delay (EKF2_GPS_DELAY).
inline constexpr double kDataflashDefaultGnssLagMs = 120;
inline constexpr double kUlogDefaultGnssLagMs = 110;

/// The boot-time fit's options for a receiver lag of `lag_ms` (ms).
inline BootTimeFitOptions boot_time_options_for_lag(double lag_ms) {
  BootTimeFitOptions o;
  o.gnss_lag_us = static_cast<std::int64_t>(lag_ms * 1000.0 + (lag_ms >= 0 ? 0.5 : -0.5));
  return o;
}

struct AutopilotAttitudeReport {
  std::string format;  ///< "px4_ulog" or "ardupilot_dataflash"
  std::size_t file_bytes = 0;
  std::size_t truncated_bytes = 0;  ///< bytes of an incomplete last message, not read

  std::string attitude_message;             ///< "vehicle_attitude" (multi_id 0) or "ATT"
  std::string attitude_time_field;          ///< "timestamp_sample", "timestamp" or "TimeUS" (boot µs)
  std::size_t attitude_messages = 0;        ///< messages of that topic / type in the log
  std::size_t attitude_samples = 0;         ///< kept, strictly increasing in time
  std::size_t attitude_invalid = 0;         ///< skipped: not a unit quaternion / angle out of range or NaN
  std::size_t attitude_not_increasing = 0;  ///< skipped: time not after the previous kept sample

  std::string gps_message;       ///< "vehicle_gps_position", "sensor_gps" (lowest multi_id) or "GPS"
  std::size_t gps_messages = 0;  ///< of that topic / type (instance 0 for DataFlash)
  std::size_t gps_skipped = 0;   ///< no 3-D fix, or no time in the message
  BootTimeFit fit;               ///< fit.used / fit.rejected: pairs kept / rejected as jumps
  double gnss_lag_ms = 0;        ///< the receiver lag the GNSS stamps were moved back by (ms)
  bool gnss_lag_given = false;   ///< given by the caller (config), not the log type's default

  UtcTime utc_start, utc_end;  ///< first and last attitude sample on the UTC axis
};

}  // namespace rangecal
