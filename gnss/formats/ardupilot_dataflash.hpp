#pragma once
// Reader of ArduPilot DataFlash binary logs (`.bin`), the self-describing format of ArduPilot's
// AP_Logger (ArduPilot developer docs, "Adding a new Log Message", and the format-character table
// of libraries/AP_Logger/LogStructure.h). Every message is the head 0xA3 0x95, a type byte, then
// the type's fields packed little-endian with no padding. Type 128, `FMT`, defines a type:
//   uint8 Type, uint8 Length (bytes of the whole message, head included), char Name[4],
//   char Format[16] (one character per field), char Columns[64] (comma-separated field names)
// — 89 bytes; a log starts with the FMT that defines FMT itself. Format characters and sizes:
//   b int8, B uint8, h int16, H uint16, i int32, I uint32, f float, d double, q int64, Q uint64,
//   M uint8 (flight mode), n char[4], N char[16], Z char[64], a int16[32],
//   c int16·0.01, C uint16·0.01, e int32·0.01, E uint32·0.01, L int32·1e-7 (degrees of lat/lon).
//
// No real DataFlash log is available to the project: this reader is tested on files the tests
// build from the layout above (tests/unit/gnss/ardupilot_dataflash_test.cpp), not on a flight log.
//
// Robustness: every length is checked against the bytes left. A type's Length must equal 3 plus
// the sizes of its format characters, its column count the number of characters, and a type may
// be defined again only identically. An incomplete last message (a log cut by power loss) ends
// the reading and is counted in `truncated_bytes`. Anything else — bytes that are not a message
// head where one must start, a message type with no FMT before it, a bad FMT — is a
// rangecal::Error of kind input (exit 3) on the file, line 0, naming the byte offset and the
// message; the reader does not skip ahead to resynchronise, so a corrupt log is reported rather
// than silently shortened. Text from the file is quoted (binary_log_bytes.hpp).
//
// Attitude (dataflash_attitude): `ATT` messages, columns TimeUS (boot µs), Roll, Pitch, Yaw in
// degrees (ArduPilot's yaw is a heading, 0…360 clockwise from north; wrapped here into
// (-180, 180]); body FRD → NED as in gnss/track/attitude.hpp. Boot time → UTC from `GPS`
// messages: TimeUS (boot µs when logged), GWk (GPS week, continuous), GMS (ms of week), Status
// (≥ 3: 3-D fix), and I (receiver instance; only instance 0 is used when the column exists). GPS
// time → UTC with the leap-second table (utc_time.hpp); messages without a 3-D fix or without a
// time (GWk 0, GMS outside the week) are skipped and counted; the rest go to fit_boot_time
// (boot_time_fit.hpp), exactly as for PX4.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gnss/formats/autopilot_attitude_report.hpp"
#include "gnss/track/attitude.hpp"

namespace rangecal {

/// One message type as its FMT message defines it.
struct DataflashFormat {
  std::uint8_t type = 0;
  std::uint8_t length = 0;  ///< bytes of one message, the 3-byte head included
  std::string name;         ///< e.g. "ATT"
  std::string format;       ///< one format character per column
  std::vector<std::string> columns;
  std::vector<std::uint16_t> offsets;  ///< of each column from the message start (head included)
  std::size_t byte_offset = 0;         ///< of its FMT message
  std::size_t messages = 0;            ///< messages of this type read
};

struct DataflashSummary {
  std::string path;
  std::size_t file_bytes = 0;
  std::size_t messages = 0;              ///< all messages, FMT included
  std::size_t truncated_bytes = 0;       ///< incomplete last message, not read
  std::vector<DataflashFormat> formats;  ///< every type defined, in order of definition (FMT first)
};

/// Called for each message that is not an FMT: its type and its bytes (head included, exactly
/// format.length bytes).
using DataflashVisitor = std::function<void(const DataflashFormat& format, std::string_view message)>;

/// True when `head` (the first bytes of a file) is a DataFlash message head of type FMT.
bool is_dataflash(std::string_view head);

/// Reads the messages of a DataFlash log held in memory in order, calling `visit` for each
/// (FMT messages are consumed by the reader). `path` is for messages. Throws rangecal::Error
/// (input) as described at the top of this file.
DataflashSummary walk_dataflash(std::string_view bytes, const std::string& path,
                                const DataflashVisitor& visit);

/// Index of the column `name` of `f`; nullopt when absent.
std::optional<std::size_t> dataflash_column(const DataflashFormat& f, std::string_view name);
/// Numeric value of a column, with its format character's scale (c C e E ×0.01, L ×1e-7);
/// nullopt for the text and array characters (n N Z a). `message` is as given to the visitor.
std::optional<double> dataflash_number(const DataflashFormat& f, std::size_t column,
                                       std::string_view message);
/// Exact value of an integer column (b B h H i I M q Q; nullopt for others, and for a Q value
/// above 2^63 − 1).
std::optional<std::int64_t> dataflash_integer(const DataflashFormat& f, std::size_t column,
                                              std::string_view message);

/// The attitude on the UTC axis as described at the top of this file, with `report` filled when
/// given. Throws rangecal::Error (input) when the log has no ATT or GPS type or misses one of
/// their columns (or has it of a non-numeric type), when the GNSS time does not determine the
/// boot-time offset (boot_time_fit.hpp), or when fewer than 2 attitude samples remain.
AttitudeSeries dataflash_attitude(std::string_view bytes, const std::string& path,
                                  AutopilotAttitudeReport* report = nullptr,
                                  std::optional<double> gnss_lag_ms = std::nullopt);
/// Reads the file, then dataflash_attitude.
AttitudeSeries read_dataflash_attitude(const std::string& path, AutopilotAttitudeReport* report = nullptr,
                                       std::optional<double> gnss_lag_ms = std::nullopt);

}  // namespace rangecal
