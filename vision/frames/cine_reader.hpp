#pragma once
// Native reader for Phantom .cine files (Vision Research), the format range cameras write and the
// only one that keeps the per-frame UTC time stamps (OpenCV/FFmpeg drop them). Layout in
// cine_format.hpp and docs/frames_and_detection.md.
//
// Supported pixel data: uncompressed 8-bit and 16-bit grey (biCompression 0, biBitCount 8/16),
// uncompressed 24/48-bit BGR (converted to grey), Phantom packed 10-bit "P10" (biCompression 256,
// 4 pixels in 5 bytes, most significant bit first) and packed 12-bit "P12L" (biCompression 1024,
// 2 pixels in 3 bytes, MSB first). Packed pixels are returned as their raw codes (bits = 10 or 12)
// — P10 codes are the camera's companded values, not linearised. Raw colour-filter-array files
// (Compression 2) are returned as the grey mosaic. JPEG (Compression 1) is rejected.
// Row order: plain BMP-style data is stored bottom-up, packed data top-down; SETUP.bFlipV and a
// negative biHeight each invert that. Returned images are always top-down.
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

struct CineHeader {
  // CINEFILEHEADER
  std::uint16_t header_size = 0;
  std::uint16_t compression = 0;  ///< 0 grey/RGB, 1 JPEG, 2 uninterpolated CFA (raw mosaic)
  std::uint16_t version = 0;
  std::int32_t first_movie_image = 0;
  std::uint32_t total_image_count = 0;
  std::int32_t first_image_no = 0;  ///< camera image number of the first saved image
  std::uint32_t image_count = 0;    ///< images saved in this file
  std::uint32_t off_image_header = 0;
  std::uint32_t off_setup = 0;
  std::uint32_t off_image_offsets = 0;
  UtcTime trigger_time;
  bool trigger_irig_locked = false;
  // BITMAPINFOHEADER
  std::int32_t bi_width = 0;
  std::int32_t bi_height = 0;  ///< as stored (negative = rows stored top-down, BMP convention)
  std::uint16_t bi_bit_count = 0;
  std::uint32_t bi_compression = 0;  ///< 0 plain, 256 packed 10-bit, 1024 packed 12-bit
  std::uint32_t bi_size_image = 0;
  // SETUP
  std::uint16_t setup_length = 0;
  std::uint32_t frame_rate = 0;  ///< frames per second
  std::uint32_t real_bpp = 0;    ///< significant bits of the sensor data
  std::uint32_t cfa = 0;         ///< colour filter array code (0 = monochrome)
  bool flip_v = false;
  std::uint32_t shutter_ns = 0;

  int width() const { return bi_width; }
  /// |biHeight|; the reader refuses INT32_MIN, whose negation overflows.
  int height() const { return bi_height < 0 ? -bi_height : bi_height; }
};

/// An open .cine file. Construction reads and validates every header, the tagged blocks and the
/// image offsets (not the pixels). read_image is const and thread-safe (positional reads).
class CineReader {
 public:
  /// Throws rangecal::Error (input) naming the file and the field when the file is missing,
  /// truncated, not a .cine, or uses an unsupported pixel format.
  explicit CineReader(const std::string& path);
  ~CineReader();
  CineReader(const CineReader&) = delete;
  CineReader& operator=(const CineReader&) = delete;

  const std::string& path() const { return path_; }
  const CineHeader& header() const { return header_; }
  std::size_t frame_count() const { return offsets_.size(); }
  /// Significant bits of the returned pixels (8, 10, 12 or 16).
  int bits() const { return bits_; }
  /// True when the file has a TIME64 block (type 1002) with one time per saved image.
  bool has_times() const { return !times_.empty(); }
  /// UTC of saved image `index` (0-based); requires has_times().
  UtcTime frame_time(std::size_t index) const { return times_.at(index); }
  bool frame_irig_locked(std::size_t index) const { return irig_.at(index); }
  /// Exposure in seconds from the type-1003 block, when present.
  std::optional<double> exposure_s(std::size_t index) const;
  /// File offset of saved image `index` (its annotation header).
  std::uint64_t image_offset(std::size_t index) const { return offsets_.at(index); }

  /// Decodes saved image `index` (0-based) to CV_8UC1 (8-bit data) or CV_16UC1, top-down.
  cv::Mat read_image(std::size_t index) const;

 private:
  std::string path_;
  int fd_ = -1;
  std::uint64_t file_size_ = 0;
  CineHeader header_;
  int bits_ = 8;
  bool stored_bottom_up_ = true;
  std::vector<std::uint64_t> offsets_;
  std::vector<UtcTime> times_;
  std::vector<bool> irig_;
  std::vector<double> exposures_;
};

}  // namespace rangecal
