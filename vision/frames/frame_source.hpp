#pragma once
// A camera's frames with their UTC times (SPEC §3.4), random access by position, decoding only
// the frames asked for. Three kinds of entries, chosen by the file extension:
//   images  .png .tif .tiff — 8/16-bit grey or colour (converted to grey at the same depth);
//   video   .avi .mkv .mp4 .mov .m4v .mpg .mpeg .webm .wmv — decoded with cv::VideoCapture,
//           `frame` is the 0-based frame index (use a lossless codec such as FFV1 for science);
//   .cine   Phantom cine, `frame` is the 0-based index of the saved image in the file.
// Sources: a timestamps CSV (`frame,file,utc`), or a .cine alone that brings its own TIME64
// stamps. Every decoded frame must match the configured sensor size.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "vision/frames/frame_timestamps_reader.hpp"
#include "vision/frames/image_frame.hpp"

namespace rangecal {

class CineReader;
struct VideoHandle;

struct FrameSourceOptions {
  int width_px = 0;   ///< required frame width (px); 0 = any
  int height_px = 0;  ///< required frame height (px); 0 = any
  /// A missing or undecodable frame is skipped (load returns nullopt with the reason) instead of
  /// throwing.
  bool allow_missing = false;
};

class FrameSource {
 public:
  /// From a timestamps CSV. Containers (.cine, videos) named by the CSV are opened here; a missing
  /// container, or a `frame` beyond a container's length, throws naming the CSV line unless
  /// options.allow_missing.
  static FrameSource from_timestamps_csv(const std::string& csv_path, const FrameSourceOptions& options);
  /// From a .cine alone, with its per-image TIME64 stamps (frame = 0-based image index).
  static FrameSource from_cine(const std::string& cine_path, const FrameSourceOptions& options);

  FrameSource(FrameSource&&) noexcept;
  FrameSource& operator=(FrameSource&&) noexcept;
  ~FrameSource();

  std::size_t size() const { return entries_.size(); }
  const std::vector<FrameTimestamp>& entries() const { return entries_; }
  const FrameTimestamp& entry(std::size_t i) const { return entries_.at(i); }
  /// The CSV (or .cine) this source was built from, for messages.
  const std::string& origin() const { return origin_; }

  /// Decodes entry i. Thread-safe (images and .cine decode concurrently; a video is decoded
  /// under its own lock). When the frame is missing/undecodable and the source allows missing
  /// frames, returns nullopt and sets *skip_reason; otherwise throws rangecal::Error (input)
  /// naming the CSV file and line (and the frame file). A frame of the wrong size always throws.
  std::optional<ImageFrame> load(std::size_t i, std::string* skip_reason = nullptr) const;

 private:
  FrameSource() = default;
  std::string origin_;
  std::vector<FrameTimestamp> entries_;
  int sensor_w_ = 0, sensor_h_ = 0;
  bool allow_missing_ = false;
  std::map<std::string, std::shared_ptr<CineReader>> cines_;
  std::map<std::string, std::shared_ptr<VideoHandle>> videos_;
  std::map<std::string, std::string> container_errors_;  ///< containers that failed to open (allow_missing)
};

/// The kind of frame file a path names, by extension (case-insensitive).
enum class FrameFileKind { image, video, cine, unknown };
FrameFileKind frame_file_kind(const std::string& path);

/// Decodes one PNG/TIFF image to CV_8UC1/CV_16UC1 (colour → grey); sets *bits. Empty Mat when it
/// cannot be decoded.
cv::Mat decode_image_file(const std::string& path, int* bits);

}  // namespace rangecal
