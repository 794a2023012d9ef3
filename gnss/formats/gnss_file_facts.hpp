#pragma once
// FileFacts (file_facts.hpp) of the range's GNSS-side inputs, each read with its own reader, so
// that what `rangecal inspect` shows is what the stages will read:
//   RTKLIB .pos         epochs by Q, time system of the column header, `obs start/end`, rate
//   PX4 ULog            messages per topic, attitude samples on UTC (boot time → UTC fit)
//   ArduPilot DataFlash messages per type, ATT samples on UTC (GPS week/ms → UTC)
//   attitude CSV        samples, UTC span, rate
//   lamp_track.csv      epochs by Q, UTC span, rate
//   pole survey         poles by role, coordinate form
//   pole picks          picks
// Each throws rangecal::Error (input) as its reader does when the file cannot be read. An
// autopilot log whose GNSS time does not give UTC is still described (counts, boot-time span),
// with a note saying why there is no UTC span.
#include <string>

#include "gnss/formats/file_facts.hpp"

namespace rangecal {

FileFacts pos_file_facts(const std::string& path);
FileFacts ulog_file_facts(const std::string& path);
FileFacts dataflash_file_facts(const std::string& path);
FileFacts attitude_csv_file_facts(const std::string& path);
FileFacts lamp_track_file_facts(const std::string& path);
FileFacts pole_survey_file_facts(const std::string& path);
FileFacts pole_picks_file_facts(const std::string& path);

}  // namespace rangecal
