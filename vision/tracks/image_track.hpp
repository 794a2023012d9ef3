#pragma once
// A camera's imported 2-D track (docs/formats.md "Imported tracks"): the target's pixel in each frame,
// measured by another tracker (DLTdv8, Argus, a hand-labelling tool, the range's own tracker) rather
// than by rangecal's lamp detector from frames. Pixels are in rangecal's convention whatever the
// file's (docs/conventions.md: u right, v down, the centre of the top-left pixel at (0, 0)).
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rangecal {

/// The target in one frame.
struct TrackedPoint {
  std::int64_t frame = 0;  ///< the file's frame number (the frame times use the same numbers)
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  ///< px, docs/conventions.md
  std::optional<double> sigma_px;                ///< the file's own 1σ per axis (px), when it gives one
  long line = 0;                                 ///< 1-based line of the file, for messages
};

struct ImageTrack {
  std::string path;                   ///< as given, for messages
  std::string format;                 ///< the format's name (vision/tracks/track_formats.hpp)
  std::vector<TrackedPoint> points;   ///< labelled frames only, strictly increasing frame numbers
  std::size_t unlabelled_frames = 0;  ///< rows the file leaves empty (NaN, blank): target not seen
  /// Lines whose label lies outside the image (a tracker's label just beyond the edge): not used, and
  /// reported by the align stage.
  std::vector<long> outside_image_lines;
};

}  // namespace rangecal
