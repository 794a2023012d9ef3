#pragma once
// Writes Phantom .cine files (layout in cine_format.hpp): the renderer's output for tests and the
// simulator, readable by CineReader, FFmpeg's cinedec and pycine/pims. One TIME64 per image
// (tagged block 1002) and one exposure per image (block 1003).
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

struct CineWriteOptions {
  /// Pixel storage: 8 (CV_8UC1 input, plain), 16 (CV_16UC1, plain, bottom-up as Phantom writes),
  /// 10 or 12 (CV_16UC1 input with values < 2^bits, Phantom packed P10 / P12L, top-down).
  int storage_bits = 16;
  int real_bpp = 0;                 ///< SETUP.RealBPP; 0 = storage_bits (8 for 8-bit storage)
  std::uint32_t frame_rate = 0;     ///< SETUP.FrameRate (fps); informational
  double exposure_s = 0.0;          ///< per-image exposure written to block 1003 (seconds, < 1)
  std::int32_t first_image_no = 0;  ///< camera number of the first saved image
  bool irig_locked = true;          ///< IRIG flag written into every TIME64
  UtcTime trigger_time;             ///< CINEFILEHEADER.TriggerTime
};

/// Writes `images` (all the same size, type per options.storage_bits) with their UTC times to
/// `path` atomically. Throws rangecal::Error (input) naming the path when the images and times
/// disagree in number, size or type, a value does not fit the storage bits, or writing fails.
void write_cine(const std::string& path, const std::vector<cv::Mat>& images,
                const std::vector<UtcTime>& times, const CineWriteOptions& options);

}  // namespace rangecal
