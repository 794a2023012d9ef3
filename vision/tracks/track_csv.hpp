#pragma once
// rangecal's own 2-D track CSV (docs/formats.md "Imported tracks"): header `frame,u,v` and optionally
// `sigma_px`, one labelled frame a line.
//   frame     integer ≥ 0, strictly increasing down the file; the frame times use the same numbers
//   u, v      px in rangecal's convention (u right, v down, the top-left pixel's centre at (0, 0)),
//             inside the image; both blank or NaN: the target was not seen in that frame
//   sigma_px  optional: the label's 1σ per axis (px, > 0, ≤ 100); blank: the camera's a-priori σ
#include <string>

#include "vision/tracks/image_track.hpp"
#include "vision/tracks/track_read_options.hpp"

namespace rangecal {

/// True when `header_line` names the columns frame, u and v.
bool is_track_csv_header(const std::string& header_line);

/// Parses the CSV text; `path` names the file in messages. Throws rangecal::Error (input).
ImageTrack parse_track_csv(const std::string& text, const std::string& path, const TrackReadOptions& options);

}  // namespace rangecal
