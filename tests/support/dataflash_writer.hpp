#pragma once
// A minimal ArduPilot DataFlash writer for tests: no real `.bin` log is available to the project,
// so the reader is tested on files built here from the format's published layout (ArduPilot
// developer docs "Adding a new Log Message", the format-character table of AP_Logger's
// LogStructure.h): messages A3 95 <type> <fields packed little-endian>; FMT (type 128, 89 bytes:
// Type, Length, Name[4], Format[16], Columns[64]) defines each type, FMT itself first.
#include <cstdint>
#include <string>
#include <vector>

namespace rangecal::test {

class DataflashWriter {
 public:
  /// Starts with the FMT message that defines FMT.
  DataflashWriter();
  /// Appends an FMT message for `type`; `length` 0 means the correct length from `format`.
  void define(int type, const std::string& name, const std::string& format, const std::string& columns,
              int length = 0);
  /// Appends a message of a defined type; one value per format character, packed by that
  /// character (c C e E scaled by 100 and rounded, L by 1e7; integers rounded; text characters
  /// written as zeros). Values are exact for integers up to 2^53.
  void message(int type, const std::vector<double>& values);
  /// Appends raw bytes (for corrupt files).
  void raw(const std::string& bytes) { bytes_ += bytes; }

  const std::string& bytes() const { return bytes_; }

  /// The formats ArduPilot 4.x uses for ATT and GPS (AP_AHRS and AP_GPS LogStructure.h):
  ///   ATT "QffffffffB" TimeUS,DesRoll,Roll,DesPitch,Pitch,DesYaw,Yaw,ErrRP,ErrYaw,AEKF
  ///   GPS "QBBIHBcLLeffffB" TimeUS,I,Status,GMS,GWk,NSats,HDop,Lat,Lng,Alt,Spd,GCrs,VZ,Yaw,U
  static constexpr int kAtt = 35, kGps = 36;
  void define_att_and_gps();
  /// One ATT message (roll, pitch, yaw in degrees as ArduPilot logs them: yaw 0…360).
  void att(std::uint64_t time_us, double roll, double pitch, double yaw);
  /// One GPS message of instance `instance`.
  void gps(std::uint64_t time_us, int status, int week, std::uint32_t week_ms, int instance = 0);

 private:
  std::string bytes_;
  std::vector<std::string> formats_ = std::vector<std::string>(256);
};

}  // namespace rangecal::test
