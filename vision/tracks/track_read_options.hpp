#pragma once
// What a track reader needs besides the file (vision/tracks/track_formats.hpp, docs/formats.md "Imported
// tracks"): the image it must lie inside, and which of a file's tracks is this camera's.

namespace rangecal {

/// Where a track's pixels are and which of a file's tracks is this camera's.
struct TrackReadOptions {
  int width_px = 0;  ///< the camera's image size: every labelled pixel must lie inside it
  int height_px = 0;
  int point = 1;   ///< xypts: the point number (`pt<point>_…`), 1-based
  int camera = 1;  ///< xypts: the camera number (`…_cam<camera>_…`), 1-based
  /// xypts: where the file's Y axis starts. DLTdv5–7 and Argus count Y up from the bottom row, DLTdv8
  /// from the top (both with the first pixel's centre at 1): the file does not say, so the config must.
  enum class YOrigin { unset, top, bottom } y_origin = YOrigin::unset;
};

}  // namespace rangecal
