#pragma once
// The frames timestamps CSV (docs/formats.md): header `frame,file,utc`, one frame a line.
//   frame  integer ≥ 0, strictly increasing down the file (frames need not be contiguous); for a
//          video, .cine or .mraw it is the 0-based index of the frame in that file
//   file   an image (PNG/TIFF), a video, a .cine or a Photron .mraw, relative to the CSV's folder
//          (or absolute)
//   utc    ISO 8601 with `Z`, 1–9 fraction digits; strictly increasing down the file
#include <cstdint>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

struct FrameTimestamp {
  std::int64_t frame = 0;
  std::string file;  ///< resolved path (CSV folder joined with the `file` field)
  UtcTime utc;
  long line = 0;  ///< 1-based line in the CSV (0 when the entry comes from a .cine alone)
};

struct FrameTimestamps {
  std::string csv_path;  ///< as given, for messages
  std::vector<FrameTimestamp> entries;
};

/// Reads and validates a timestamps CSV. Throws rangecal::Error (input) naming the CSV, line and
/// field for a missing column, a bad frame number, an empty file name, an unparsable time, or a
/// frame number or time not strictly after the previous line's. File existence is not checked
/// here (the frame source decides whether a missing frame is fatal).
FrameTimestamps read_frame_timestamps(const std::string& csv_path);

/// As read_frame_timestamps from text in memory; `csv_path` names the file in messages and its
/// folder resolves relative `file` fields.
FrameTimestamps parse_frame_timestamps(const std::string& text, const std::string& csv_path);

}  // namespace rangecal
