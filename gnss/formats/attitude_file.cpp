#include "gnss/formats/attitude_file.hpp"

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "gnss/formats/ardupilot_dataflash.hpp"
#include "gnss/formats/attitude_csv.hpp"
#include "gnss/formats/px4_ulog.hpp"

namespace rangecal {

const char* to_string(AttitudeFileKind k) {
  switch (k) {
    case AttitudeFileKind::csv:
      return "csv";
    case AttitudeFileKind::px4_ulog:
      return "px4_ulog";
    case AttitudeFileKind::ardupilot_dataflash:
      return "ardupilot_dataflash";
    case AttitudeFileKind::unknown_binary:
      return "unknown_binary";
  }
  return "csv";
}

AttitudeFileKind attitude_file_kind(std::string_view head) {
  if (head.substr(0, 4) == "ULog") return AttitudeFileKind::px4_ulog;
  if (head.size() >= 2 && static_cast<unsigned char>(head[0]) == 0xA3 &&
      static_cast<unsigned char>(head[1]) == 0x95)
    return AttitudeFileKind::ardupilot_dataflash;
  for (char c : head.substr(0, 4096))
    if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r')
      return AttitudeFileKind::unknown_binary;
  return AttitudeFileKind::csv;
}

AttitudeSeries read_attitude_file(const std::string& path, AttitudeFileReport* report,
                                  std::optional<double> gnss_lag_ms) {
  std::string bytes = read_file_text(path);
  AttitudeFileReport rep;
  rep.kind = attitude_file_kind(bytes);
  AttitudeSeries s;
  switch (rep.kind) {
    case AttitudeFileKind::px4_ulog: {
      AutopilotAttitudeReport r;
      s = ulog_attitude(parse_ulog(std::move(bytes), path), &r, gnss_lag_ms);
      rep.log = r;
      break;
    }
    case AttitudeFileKind::ardupilot_dataflash: {
      AutopilotAttitudeReport r;
      s = dataflash_attitude(bytes, path, &r, gnss_lag_ms);
      rep.log = r;
      break;
    }
    case AttitudeFileKind::csv:
      s = parse_attitude_csv(bytes, path);
      break;
    case AttitudeFileKind::unknown_binary:
      throw_input_error(
          path, 0, "",
          "a binary file that is neither a PX4 ULog (starting 'ULog') nor an ArduPilot DataFlash log "
          "(starting A3 95), and not an attitude CSV (utc,roll_deg,pitch_deg,yaw_deg)");
  }
  rep.samples = s.samples.size();
  if (!s.samples.empty()) rep.utc_start = s.samples.front().utc, rep.utc_end = s.samples.back().utc;
  if (report) *report = rep;
  return s;
}

}  // namespace rangecal
