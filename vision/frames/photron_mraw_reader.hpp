#pragma once
// Random access to the frames of a Photron .mraw (Photron FASTCAM Viewer "MRaw"): frames stored
// back to back with no header of their own, described by the .cihx/.cih beside the file
// (photron_cih.hpp). Pixel layouts (docs/frames_and_detection.md "Photron FASTCAM"):
//   8 bit    one byte per pixel                                   → CV_8UC1
//   16 bit   one little-endian uint16 per pixel                   → CV_16UC1
//   12 bit   packed, two pixels in three bytes, most significant bit first:
//            p0 = b0 << 4 | b1 >> 4,  p1 = (b1 & 0xF) << 8 | b2    → CV_16UC1
// Rows top-down, no row padding. Effective bits (`effectiveBit`): on the Lower side the values are
// returned as stored; on the Higher side they are shifted right by (stored − effective) bits, so
// every returned value lies in [0, 2^effective − 1] and ImageFrame::bits = the effective depth.
#include <cstdint>
#include <string>

#include "vision/frames/image_frame.hpp"
#include "vision/frames/photron_cih.hpp"

namespace rangecal {

/// An open .mraw with its header. Construction reads the header and checks the .mraw's size
/// against width × height × bits × frames (exact match; overflow-safe) before any pixel is read.
/// read_frame is const and thread-safe (positional reads on one descriptor, no shared state).
class PhotronMrawReader {
 public:
  /// Opens `mraw_path` with the header found beside it (find_photron_header: .cihx preferred).
  explicit PhotronMrawReader(const std::string& mraw_path);
  /// Opens `mraw_path` with an explicitly named header.
  PhotronMrawReader(const std::string& mraw_path, const std::string& header_path);
  ~PhotronMrawReader();
  PhotronMrawReader(const PhotronMrawReader&) = delete;
  PhotronMrawReader& operator=(const PhotronMrawReader&) = delete;

  const std::string& path() const { return path_; }
  const PhotronHeader& header() const { return header_; }
  std::int64_t frame_count() const { return header_.total_frame; }
  /// Significant bits of the returned pixels (the header's effective depth).
  int bits() const { return header_.effective_depth; }

  /// Decodes frame `index` (0-based position in the file). The result's `frame` is the index and
  /// `utc` is left at 0 (the frame source sets it). Throws rangecal::Error (input) naming the
  /// .mraw and the frame when the index is out of range or the read fails.
  ImageFrame read_frame(std::int64_t index) const;

 private:
  void open(const std::string& header_path);

  std::string path_;
  int fd_ = -1;
  PhotronHeader header_;
};

}  // namespace rangecal
