#pragma once
// A camera's frames with their UTC times (docs/formats.md), random access by position, decoding only
// the frames asked for. Each frame file is opened as a FrameContainer of the format its extension
// selects (frame_formats.hpp: images .png .tif .tiff, videos, Phantom .cine, Photron .mraw).
// Sources: a timestamps CSV (`frame,file,utc`), or one file alone whose format brings its own times
// (a .cine's TIME64 stamps, a .mraw's header clock and record rate). Every decoded frame must match
// the configured sensor size. time_source() says where the frame times came from.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vision/frames/frame_container.hpp"
#include "vision/frames/frame_formats.hpp"
#include "vision/frames/frame_timestamps_reader.hpp"
#include "vision/frames/image_decoding.hpp"  // decode_image_file and kin, for callers of the frame source
#include "vision/frames/image_frame.hpp"

namespace rangecal {

struct FrameSourceOptions {
  int width_px = 0;   ///< required frame width (px); 0 = any
  int height_px = 0;  ///< required frame height (px); 0 = any
  /// A missing or undecodable frame is skipped (load returns nullopt with the reason) instead of
  /// throwing.
  bool allow_missing = false;
};

class FrameSource {
 public:
  /// From a timestamps CSV. Containers (.cine, .mraw, videos) named by the CSV are opened here; a
  /// missing container, or a `frame` beyond a container's length, throws naming the CSV line unless
  /// options.allow_missing. A file of no known format always throws.
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
  /// From one file alone of a format that brings its own times (format.own_time_source), frame =
  /// 0-based index; `clock_utc_offset_h` reaches formats that stamp the camera's local clock.
  /// Throws rangecal::Error (input) as the format's reader does when the file has no usable times.
  static FrameSource from_file_alone(const FrameFormat& format, const std::string& path,
                                     const FrameSourceOptions& options,
                                     std::optional<double> clock_utc_offset_h);

  FrameSource(FrameSource&&) noexcept;
  FrameSource& operator=(FrameSource&&) noexcept;
  ~FrameSource();

  std::size_t size() const { return entries_.size(); }
  const std::vector<FrameTimestamp>& entries() const { return entries_; }
  const FrameTimestamp& entry(std::size_t i) const { return entries_.at(i); }
  /// The CSV (or the file alone) this source was built from, for messages.
  const std::string& origin() const { return origin_; }
  /// Where the frame times come from, for run.json: kTimeSourceCsv, or the own_time_source of the
  /// format of a file alone (frame_formats.hpp).
  const std::string& time_source() const { return time_source_; }
  static constexpr const char* kTimeSourceCsv = "timestamps CSV";

  /// Decodes entry i with the container of its file. Thread-safe (images, .cine and .mraw decode
  /// concurrently; a video is decoded under its own lock). When the frame is missing/undecodable
  /// and the source allows missing frames, returns nullopt and sets *skip_reason; otherwise throws
  /// rangecal::Error (input) naming the CSV file and line (and the frame file). A frame of the
  /// wrong size always throws.
  std::optional<ImageFrame> load(std::size_t i, std::string* skip_reason = nullptr) const;

 private:
  FrameSource() = default;
  std::string origin_;
  std::string time_source_;
  std::vector<FrameTimestamp> entries_;
  int sensor_w_ = 0, sensor_h_ = 0;
  bool allow_missing_ = false;
  std::map<std::string, std::unique_ptr<FrameContainer>> containers_;  ///< by file path
  std::map<std::string, std::string> container_errors_;  ///< containers that failed to open (allow_missing)
};

}  // namespace rangecal
