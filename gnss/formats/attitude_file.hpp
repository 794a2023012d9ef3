#pragma once
// The attitude file of a mission (config `attitude.file`), whatever wrote it, chosen by content,
// never by file name:
//   - `ULog` first: a PX4 ULog (px4_ulog.hpp; its parser then checks the whole 7-byte magic
//     `ULog` 01 12 35, so a damaged header is reported as such, not read as CSV);
//   - A3 95 first: an ArduPilot DataFlash log (ardupilot_dataflash.hpp; its first message must
//     be the FMT of type 128, anything else is reported by that reader);
//   - any other file holding a control byte (other than tab, CR, LF) in its first 4 KiB: an
//     error, since it is binary but of no known kind (and a CSV error would echo its bytes);
//   - else the hand-made CSV `utc,roll_deg,pitch_deg,yaw_deg` (attitude_csv.hpp).
// Every reader returns the same AttitudeSeries on UTC, in the conventions of
// gnss/track/attitude.hpp.
#include <optional>
#include <string>
#include <string_view>

#include "gnss/formats/autopilot_attitude_report.hpp"
#include "gnss/track/attitude.hpp"

namespace rangecal {

enum class AttitudeFileKind { csv, px4_ulog, ardupilot_dataflash, unknown_binary };
const char* to_string(AttitudeFileKind k);

/// Which reader a file's first bytes call for.
AttitudeFileKind attitude_file_kind(std::string_view head);

struct AttitudeFileReport {
  AttitudeFileKind kind = AttitudeFileKind::csv;
  std::size_t samples = 0;
  UtcTime utc_start, utc_end;                  ///< first and last sample
  std::optional<AutopilotAttitudeReport> log;  ///< the autopilot reader's report (ULog, DataFlash)
};

/// Reads the attitude file at `path` with the reader its content calls for, filling `report` when
/// given. Throws rangecal::Error (input) as each reader does, and for a missing or unreadable file.
/// `gnss_lag_ms`: an autopilot log's GNSS receiver lag (ms; none: the log type's default,
/// autopilot_attitude_report.hpp); a CSV is on UTC already and takes none.
AttitudeSeries read_attitude_file(const std::string& path, AttitudeFileReport* report = nullptr,
                                  std::optional<double> gnss_lag_ms = std::nullopt);

}  // namespace rangecal
