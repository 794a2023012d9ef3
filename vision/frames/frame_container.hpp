#pragma once
// One frame file opened for reading, whatever its format (the formats are listed in
// frame_formats.hpp): how many frames it holds, frame k decoded to the uniform ImageFrame, and,
// for formats that carry them, the frames' own time stamps. FrameSource holds one container per
// file a camera's frames name, and `rangecal inspect` reads the same files with the same readers.
//
// Thread-safety: decode() may be called concurrently from several threads; a format whose decoder
// keeps state (a video's position) serialises inside its own container.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"
#include "vision/frames/image_frame.hpp"

namespace rangecal {

/// Why a frame was not decoded; empty `reason` when it was. A missing or undecodable frame is
/// skipped by a source that allows missing frames; a frame whose header already shows the wrong
/// size never is.
struct FrameDecodeProblem {
  std::string reason;
  bool wrong_size = false;
};

class FrameContainer {
 public:
  virtual ~FrameContainer() = default;

  /// Frames in the file; nullopt when the file does not bound the frame numbers (an image file is
  /// one frame, whatever number a timestamps CSV gives it).
  virtual std::optional<std::int64_t> frame_count() const = 0;

  /// Decodes frame `frame` into out.image and out.bits. `sensor_w`/`sensor_h` (px, 0 = any) let a
  /// format refuse a frame of the wrong size from its header before paying for the decode.
  virtual FrameDecodeProblem decode(std::int64_t frame, int sensor_w, int sensor_h,
                                    ImageFrame& out) const = 0;

  /// The UTC time of every frame, from the file alone, for formats whose registry entry says they
  /// can stand without a timestamps CSV. `clock_utc_offset_h` is the camera clock − UTC (hours) for
  /// formats that stamp the camera's local clock. Throws rangecal::Error (input) naming the file
  /// when the times cannot be had; the default throws because the format has none.
  virtual std::vector<UtcTime> own_times(std::optional<double> clock_utc_offset_h) const;
};

/// "frame '<file>' (frame <k>) is <w>x<h> px<how>; the sensor is <sw>x<sh>": the one wording of a
/// frame of the wrong size, whichever step finds it.
std::string frame_size_mismatch(const std::string& file, std::int64_t frame, int w, int h,
                                const std::string& how, int sensor_w, int sensor_h);

/// "frame <k> is beyond the end of '<file>'".
std::string frame_beyond_end(const std::string& file, std::int64_t frame);

}  // namespace rangecal
