#pragma once
// Reader of PX4 ULog flight logs (PX4 user guide, "ULog File Format"; the section names below are
// that document's). A 16-byte header (`ULog` 0x01 0x12 0x35, version, start time in µs), then
// messages, each a 3-byte header (uint16 size of the body, uint8 type) and a body:
//   B flag bits (version 1, first message only), F format, I info, M multi-info, P parameter,
//   Q default parameter, A add subscription, R remove subscription, D data, L / C logged string
//   (plain / tagged), S sync, O dropout. As "Requirements for Parsers" asks: unknown message
//   types are skipped (and counted), versions other than 1 are parsed as well (and reported),
//   unknown incompatible flag bits make the log unreadable (an error), and a log ending inside a
//   message is read up to that message.
// Formats ("Format Message") are `name:type field;type field;…` with the C types of "Data
// Types", fixed arrays `type[n]`, and nested formats by name (possibly defined after their use);
// fields named `_padding…` are alignment only, and trailing padding of a top-level format is not
// written in its D messages.
// Little-endian throughout. Data appended after a crash (incompat flag DATA_APPENDED, "Flag Bits
// Message") is read from each appended offset.
//
// Robustness: the whole file is read into memory and every length is checked against the bytes
// left before it is used; formats are bounded (a D message carries at most 65533 data bytes, so no
// format may be larger) and nested at most 32 deep. An incomplete last message (a log cut by power
// loss) ends the reading and is counted in `truncated_bytes`; anything else malformed is a
// rangecal::Error of kind input (exit 3) on the file, line 0, the field naming the message type
// and topic/field (e.g. "D vehicle_attitude", "F vehicle_attitude.q"), the reason stating the byte
// offset. Text from the file is quoted (binary_log_bytes.hpp), never echoed raw.
//
// Attitude (ulog_attitude): topic `vehicle_attitude`, multi_id 0: quaternion `q` [w, x, y, z]
// (float[4], rotating body FRD into NED) → roll, pitch, yaw (attitude_from_quaternion), on the boot
// time `timestamp_sample` when the format has it (the time of the IMU sample the estimate belongs
// to, newer PX4), else `timestamp` (the time it was published). Boot time → UTC from the GNSS
// messages of the same log: topic `vehicle_gps_position` (the receiver PX4 selected or blended),
// else `sensor_gps` with the lowest multi_id; each message gives `time_utc_usec` (UTC µs since 1970
// of the fix) at boot time `timestamp` + `timestamp_time_relative` (the latter when the format has
// it: PX4 defines their sum as the boot time of the UTC reading). Messages with fix_type < 3 or
// time_utc_usec = 0 are skipped and counted; the rest go to fit_boot_time (boot_time_fit.hpp).
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gnss/formats/autopilot_attitude_report.hpp"
#include "gnss/track/attitude.hpp"

namespace rangecal {

/// The C types of "Data Types", and `nested` for a field whose type is another format.
enum class UlogType : std::uint8_t {
  int8,
  uint8,
  int16,
  uint16,
  int32,
  uint32,
  int64,
  uint64,
  float32,
  float64,
  boolean,
  character,
  nested
};
/// Bytes of one element (0 for nested).
std::size_t ulog_type_size(UlogType t);

struct UlogField {
  std::string name;
  std::string type_name;  ///< as written: "float", "uint8_t", or a format name
  UlogType type = UlogType::uint8;
  std::size_t nested = 0;    ///< index into UlogLog::formats when type == nested
  std::uint32_t count = 1;   ///< elements (1 for a scalar)
  bool is_array = false;     ///< written as type[count]
  std::uint32_t offset = 0;  ///< bytes from the start of the format's data
  std::uint32_t size = 0;    ///< bytes of the whole field
};

struct UlogFormat {
  std::string name;
  std::vector<UlogField> fields;
  std::uint32_t size = 0;         ///< bytes, padding included
  std::uint32_t logged_size = 0;  ///< bytes a D message carries: size less trailing `_padding` fields
  std::size_t byte_offset = 0;    ///< of its F message
};

struct UlogSubscription {
  std::uint16_t msg_id = 0;
  std::uint8_t multi_id = 0;
  std::string topic;
  std::size_t format = 0;  ///< index into UlogLog::formats
  std::size_t byte_offset = 0;
  std::size_t messages = 0;  ///< D messages read for it
};

/// One D message: its subscription and where its data (after msg_id) lies in UlogLog::bytes.
struct UlogDataMessage {
  std::size_t subscription = 0;  ///< index into UlogLog::subscriptions
  std::size_t offset = 0;
  std::size_t size = 0;
};

/// An I message: key "type name" split, value as text (strings unquoted up to their first NUL,
/// numbers in decimal, arrays as [a, b, …]; bytes outside printable ASCII as \xNN).
struct UlogInfo {
  std::string key;
  std::string type;
  std::string value;
};

struct UlogTopicCount {
  std::string topic;
  int multi_id = 0;
  std::size_t messages = 0;
};

/// What an `inspect` needs to show of a log.
struct UlogSummary {
  std::string path;
  std::size_t file_bytes = 0;
  int version = 0;                        ///< header version byte (1 today; other versions are read as well)
  std::uint64_t header_timestamp_us = 0;  ///< header: logging start, boot µs
  std::vector<UlogInfo> info;             ///< I messages in file order
  std::map<std::string, std::size_t> multi_info;  ///< M keys → values (continuations joined)
  std::size_t parameters = 0;                     ///< P messages
  std::size_t default_parameters = 0;             ///< Q messages
  std::size_t logged_strings = 0;                 ///< L and C messages
  std::size_t syncs = 0;                          ///< S messages
  std::size_t unknown_messages = 0;               ///< messages of a type this reader does not know (skipped)
  std::vector<UlogTopicCount> topics;             ///< every subscription, sorted by topic then multi_id
  /// Smallest and largest nonzero top-level uint64 `timestamp` over all D messages (boot µs);
  /// none without such data.
  std::optional<std::uint64_t> first_timestamp_us, last_timestamp_us;
  std::size_t dropouts = 0;         ///< O messages
  std::uint64_t dropout_ms = 0;     ///< their total duration
  std::size_t truncated_bytes = 0;  ///< incomplete last message(s), not read
  bool data_appended = false;       ///< flag bit DATA_APPENDED set

  /// Value of the I message `key` (e.g. "sys_name", "ver_sw"); nullopt when absent.
  std::optional<std::string> info_value(std::string_view key) const;
};

/// A parsed log: the bytes, the resolved formats, subscriptions and an index of the D messages.
struct UlogLog {
  UlogSummary summary;
  std::string bytes;
  std::vector<UlogFormat> formats;
  std::vector<UlogSubscription> subscriptions;  ///< every A message, in file order
  std::vector<UlogDataMessage> data;            ///< every D message, in file order
};

/// True when `head` (the first bytes of a file) starts with the ULog magic.
bool is_ulog(std::string_view head);

/// Parses a ULog held in memory; `path` is for messages. Throws rangecal::Error (input) as above.
UlogLog parse_ulog(std::string bytes, const std::string& path);
/// Reads and parses a ULog file (missing or unreadable file: rangecal::Error, input).
UlogLog read_ulog(const std::string& path);

/// A field reached from a format by a dotted path into nested formats ("q", "parent.child"; an
/// array of a nested format is entered at its first element).
struct UlogFieldRef {
  UlogType type = UlogType::uint8;
  std::uint32_t offset = 0;  ///< bytes from the start of the data
  std::uint32_t count = 1;
};
/// The field `path` of format `format`; nullopt when there is no such field.
std::optional<UlogFieldRef> find_ulog_field(const UlogLog& log, std::size_t format, std::string_view path);

/// Element `index` of a numeric or bool field of a D message, as a double (64-bit integers
/// above 2^53 round). The field must lie inside the message: guaranteed for fields within the
/// format's logged_size, checked otherwise (rangecal::Error, input).
double ulog_number(const UlogLog& log, const UlogDataMessage& m, const UlogFieldRef& f,
                   std::uint32_t index = 0);

/// The attitude on the UTC axis as described at the top of this file, with `report` filled when
/// given. Throws rangecal::Error (input) when the log has no vehicle_attitude or GNSS topic, when
/// their fields are missing or of the wrong type, when the GNSS time does not determine the
/// boot-time offset (boot_time_fit.hpp), or when fewer than 2 attitude samples remain.
/// `gnss_lag_ms`: the receiver lag (ms) the GNSS stamps are moved back by; none: kUlogDefaultGnssLagMs.
AttitudeSeries ulog_attitude(const UlogLog& log, AutopilotAttitudeReport* report = nullptr,
                             std::optional<double> gnss_lag_ms = std::nullopt);
/// read_ulog then ulog_attitude.
AttitudeSeries read_ulog_attitude(const std::string& path, AutopilotAttitudeReport* report = nullptr,
                                  std::optional<double> gnss_lag_ms = std::nullopt);

}  // namespace rangecal
