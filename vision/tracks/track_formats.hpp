#pragma once
// The registry of imported 2-D track formats (docs/formats.md "Imported tracks"): one row per format —
// its name (the config's `track.format`), how to recognise it from its header line, and its reader.
// A new format is one reader file and one row in track_formats.cpp.
//   csv     `frame,u,v[,sigma_px]`: rangecal's own (vision/tracks/track_csv.hpp)
//   xypts   DLTdv / Argus `xypts.csv`: `pt1_cam1_X,pt1_cam1_Y,…`, one row per frame
//           (vision/tracks/xypts_csv.hpp)
#include <functional>
#include <string>
#include <vector>

#include "vision/tracks/image_track.hpp"
#include "vision/tracks/track_read_options.hpp"

namespace rangecal {

struct TrackFormat {
  std::string name;
  std::string description;  ///< for messages: what a file of this format starts with
  /// True when the file's first non-comment line is this format's header.
  std::function<bool(const std::string& header_line)> recognises;
  std::function<ImageTrack(const std::string& text, const std::string& path, const TrackReadOptions&)> read;
};

/// Every format, in the order they are tried on a file without `format`.
const std::vector<TrackFormat>& track_formats();

/// The format named `name`, or nullptr.
const TrackFormat* find_track_format(const std::string& name);

/// Reads `path` as `format` (empty: recognised from the header line). Throws rangecal::Error (input)
/// naming the file, line and field: an unknown or unrecognised format, a bad number, a pixel outside
/// the image, frames out of order, a file without any labelled frame.
ImageTrack read_image_track(const std::string& path, const std::string& format,
                            const TrackReadOptions& options);

}  // namespace rangecal
