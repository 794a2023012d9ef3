#include "vision/tracks/xypts_csv.hpp"

#include <regex>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "vision/tracks/tracked_pixel.hpp"

namespace rangecal {

bool is_xypts_header(const std::string& header_line) {
  static const std::regex first(R"(^\s*"?pt\d+_cam\d+_X"?\s*(,|$))");
  return std::regex_search(header_line, first);
}

ImageTrack parse_xypts_csv(const std::string& text, const std::string& path,
                           const TrackReadOptions& options) {
  const CsvTable t = parse_csv(text, path);
  const std::string prefix =
      "pt" + std::to_string(options.point) + "_cam" + std::to_string(options.camera) + "_";
  const std::optional<std::size_t> c_x = t.find_column(prefix + "X"), c_y = t.find_column(prefix + "Y");
  if (!c_x || !c_y)
    throw_input_error(path, t.header_line, prefix + "X",
                      "no columns " + prefix + "X and " + prefix + "Y (track.point " +
                          std::to_string(options.point) + ", track.camera " + std::to_string(options.camera) +
                          "); the header has " + std::to_string(t.header.size()) + " columns");
  if (options.y_origin == TrackReadOptions::YOrigin::unset)
    throw_input_error(path, t.header_line, prefix + "Y",
                      "an xypts file does not say where its Y axis starts: give track.y_origin \"bottom\" "
                      "(DLTdv5-7, Argus) or \"top\" (DLTdv8)");
  const bool from_bottom = options.y_origin == TrackReadOptions::YOrigin::bottom;
  ImageTrack track;
  track.path = path;
  track.format = "xypts";
  // Data row k is frame k (1-based), counted over every data record (blank and '#' lines are not rows).
  std::int64_t frame = 0;
  for (const CsvRecord& r : t.records) {
    ++frame;
    const std::optional<double> x = track_coordinate(t, r, *c_x), y = track_coordinate(t, r, *c_y);
    if (x.has_value() != y.has_value())
      throw_input_error(path, r.line, x ? prefix + "Y" : prefix + "X",
                        "one of X and Y is given and the other is NaN");
    if (!x) {
      ++track.unlabelled_frames;
      continue;
    }
    TrackedPoint p;
    p.frame = frame;
    p.uv = Eigen::Vector2d(*x - 1, from_bottom ? options.height_px - *y : *y - 1);
    p.line = r.line;
    if (!pixel_inside(p.uv, options.width_px, options.height_px)) {
      track.outside_image_lines.push_back(r.line);
      continue;
    }
    track.points.push_back(p);
  }
  return track;
}

}  // namespace rangecal
