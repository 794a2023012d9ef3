#pragma once
// A camera's frames with their UTC times (docs/formats.md), random access by position, decoding only
// the frames asked for. Three kinds of entries, chosen by the file extension:
//   images  .png .tif .tiff — 8/16-bit grey or colour (converted to grey at the same depth);
//   video   .avi .mkv .mp4 .mov .m4v .mpg .mpeg .webm .wmv — decoded with cv::VideoCapture,
//           `frame` is the 0-based frame index (use a lossless codec such as FFV1 for science);
//   .cine   Phantom cine, `frame` is the 0-based index of the saved image in the file;
//   .mraw   Photron FASTCAM frames (header .cihx/.cih beside it), `frame` is the 0-based frame
//           index in the file.
// Sources: a timestamps CSV (`frame,file,utc`), a .cine alone that brings its own TIME64 stamps,
// or a .mraw alone timed by its header clock and record rate. Every decoded frame must match the
// configured sensor size. time_source() says where the frame times came from.
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
class PhotronMrawReader;
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
  /// From a Photron .mraw alone (frame = 0-based index), timed by its header: date and time of the
  /// camera clock, record rate, start frame and save step (photron_frame_clock).
  /// `clock_utc_offset_h` is the camera clock − UTC in hours: Photron's date and time are the
  /// camera's local clock with no zone, so without it the source is refused with a message to
  /// give a timestamps CSV; so is a header without a usable time.
  static FrameSource from_mraw(const std::string& mraw_path, const FrameSourceOptions& options,
                               std::optional<double> clock_utc_offset_h);

  FrameSource(FrameSource&&) noexcept;
  FrameSource& operator=(FrameSource&&) noexcept;
  ~FrameSource();

  std::size_t size() const { return entries_.size(); }
  const std::vector<FrameTimestamp>& entries() const { return entries_; }
  const FrameTimestamp& entry(std::size_t i) const { return entries_.at(i); }
  /// The CSV (or .cine) this source was built from, for messages.
  const std::string& origin() const { return origin_; }
  /// Where the frame times come from, for run.json: kTimeSourceCsv, kTimeSourceCine or
  /// kTimeSourceMrawHeader.
  const std::string& time_source() const { return time_source_; }
  static constexpr const char* kTimeSourceCsv = "timestamps CSV";
  static constexpr const char* kTimeSourceCine = ".cine TIME64 stamps";
  static constexpr const char* kTimeSourceMrawHeader = "mraw header + rate";

  /// Decodes entry i. Thread-safe (images, .cine and .mraw decode concurrently; a video is decoded
  /// under its own lock). When the frame is missing/undecodable and the source allows missing
  /// frames, returns nullopt and sets *skip_reason; otherwise throws rangecal::Error (input)
  /// naming the CSV file and line (and the frame file). A frame of the wrong size always throws.
  std::optional<ImageFrame> load(std::size_t i, std::string* skip_reason = nullptr) const;

 private:
  FrameSource() = default;
  std::string origin_;
  std::string time_source_;
  std::vector<FrameTimestamp> entries_;
  int sensor_w_ = 0, sensor_h_ = 0;
  bool allow_missing_ = false;
  std::map<std::string, std::shared_ptr<CineReader>> cines_;
  std::map<std::string, std::shared_ptr<VideoHandle>> videos_;
  std::map<std::string, std::shared_ptr<PhotronMrawReader>> mraws_;
  std::map<std::string, std::string> container_errors_;  ///< containers that failed to open (allow_missing)
};

/// The kind of frame file a path names, by extension (case-insensitive).
enum class FrameFileKind { image, video, cine, mraw, unknown };
FrameFileKind frame_file_kind(const std::string& path);

/// Decodes one PNG/TIFF image to CV_8UC1/CV_16UC1 (colour → grey); sets *bits. Empty Mat when it
/// cannot be decoded.
cv::Mat decode_image_file(const std::string& path, int* bits);
/// The same from the file's bytes.
cv::Mat decode_image_bytes(const std::vector<unsigned char>& bytes, int* bits);

/// Width and height (px) a PNG's IHDR or a TIFF's first IFD declares, read without decoding;
/// nullopt for other files or a header too short to say. Values beyond INT32_MAX are clamped.
std::optional<cv::Size> image_header_size(const std::vector<unsigned char>& bytes);

}  // namespace rangecal
