#include "vision/tracks/track_csv.hpp"

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "vision/tracks/tracked_pixel.hpp"

namespace rangecal {

bool is_track_csv_header(const std::string& header_line) {
  const std::vector<std::string> cols = split_trim(header_line, ',');
  auto has = [&cols](const char* name) {
    for (const std::string& c : cols)
      if (c == name) return true;
    return false;
  };
  return has("frame") && has("u") && has("v");
}

ImageTrack parse_track_csv(const std::string& text, const std::string& path,
                           const TrackReadOptions& options) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t c_frame = t.column("frame"), c_u = t.column("u"), c_v = t.column("v");
  const std::optional<std::size_t> c_sigma = t.find_column("sigma_px");
  ImageTrack track;
  track.path = path;
  track.format = "csv";
  std::int64_t previous_frame = -1;
  long previous_line = 0;
  for (const CsvRecord& r : t.records) {
    const std::int64_t frame = t.integer(r, c_frame);
    if (frame < 0) throw_input_error(path, r.line, "frame", "negative frame number " + std::to_string(frame));
    if (frame <= previous_frame)
      throw_input_error(path, r.line, "frame",
                        "frame " + std::to_string(frame) + " is not after line " +
                            std::to_string(previous_line) + "'s frame " + std::to_string(previous_frame) +
                            " (frames must increase down the file)");
    previous_frame = frame;
    previous_line = r.line;
    const std::optional<double> u = track_coordinate(t, r, c_u), v = track_coordinate(t, r, c_v);
    if (u.has_value() != v.has_value())
      throw_input_error(path, r.line, u ? "v" : "u", "one of u and v is given and the other is blank");
    if (!u) {
      ++track.unlabelled_frames;
      continue;
    }
    TrackedPoint p;
    p.frame = frame;
    p.uv = Eigen::Vector2d(*u, *v);
    p.line = r.line;
    if (!pixel_inside(p.uv, options.width_px, options.height_px)) {
      track.outside_image_lines.push_back(r.line);
      continue;
    }
    if (c_sigma && !t.text(r, *c_sigma).empty())
      p.sigma_px = t.number_in(r, *c_sigma, 1e-6, 100, "the label's 1σ per axis in pixels, > 0 and ≤ 100");
    track.points.push_back(p);
  }
  return track;
}

}  // namespace rangecal
