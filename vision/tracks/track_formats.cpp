#include "vision/tracks/track_formats.hpp"

#include <string_view>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "vision/tracks/track_csv.hpp"
#include "vision/tracks/xypts_csv.hpp"

namespace rangecal {

namespace {

// The first line that is not blank or a '#' comment, as the CSV reader skips them.
std::string header_line_of(const std::string& text) {
  std::size_t pos = 0;
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) pos = 3;
  while (pos < text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    const std::string_view line = trim(std::string_view(text).substr(pos, end - pos));
    if (!line.empty() && line.front() != '#') return std::string(line);
    pos = end + 1;
  }
  return {};
}

}  // namespace

const std::vector<TrackFormat>& track_formats() {
  static const std::vector<TrackFormat> formats = {
      {"csv", "a header `frame,u,v[,sigma_px]`", is_track_csv_header, parse_track_csv},
      {"xypts", "a DLTdv / Argus header `pt1_cam1_X,pt1_cam1_Y,...`", is_xypts_header, parse_xypts_csv},
  };
  return formats;
}

const TrackFormat* find_track_format(const std::string& name) {
  for (const TrackFormat& f : track_formats())
    if (f.name == name) return &f;
  return nullptr;
}

ImageTrack read_image_track(const std::string& path, const std::string& format,
                            const TrackReadOptions& options) {
  const std::string text = read_file_text(path);
  const TrackFormat* chosen = nullptr;
  std::string kinds;
  for (const TrackFormat& f : track_formats())
    kinds += (kinds.empty() ? "" : "; ") + f.name + ": " + f.description;
  if (!format.empty()) {
    chosen = find_track_format(format);
    if (!chosen)
      throw_input_error(path, 0, "format", "unknown track format '" + format + "' (" + kinds + ")");
  } else {
    const std::string header = header_line_of(text);
    for (const TrackFormat& f : track_formats())
      if (f.recognises(header)) {
        chosen = &f;
        break;
      }
    if (!chosen)
      throw_input_error(path, 1, "",
                        "not a 2-D track file: its first line '" + header.substr(0, 80) +
                            "' is none of the track formats (" + kinds + ")");
  }
  ImageTrack track = chosen->read(text, path, options);
  if (track.points.empty())
    throw_input_error(
        path, 0, "",
        "no labelled frame (" + std::to_string(track.unlabelled_frames) + " rows, every one blank or NaN)");
  return track;
}

}  // namespace rangecal
