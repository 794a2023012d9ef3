#pragma once
// The uniform frame value type every frame source returns (docs/formats.md). Pixels keep their native
// depth — no conversion pass, so the detector's full-frame search reads 8-bit frames at one byte
// per pixel — in a single-channel cv::Mat:
//   CV_8UC1   8-bit sources (PNG/TIFF 8-bit, video, .cine 8-bit);
//   CV_16UC1  everything deeper: 16-bit PNG/TIFF, .cine 16-bit, unpacked 10/12-bit .cine.
// `bits` says how many of the container's bits are significant (8, 10, 12, 14 or 16), so the
// saturation level is (1 << bits) − 1 whatever the container. Colour images are converted to
// grey (cv::COLOR_BGR2GRAY, same depth) when decoded.
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

struct ImageFrame {
  std::int64_t frame = 0;  ///< frame number as the source names it (CSV `frame`, video/.cine index)
  UtcTime utc;             ///< exposure time stamp (UTC)
  cv::Mat image;           ///< CV_8UC1 or CV_16UC1, rows top-down (row 0 is the image top, v = 0)
  int bits = 8;            ///< significant bits per pixel (8…16); saturation = (1 << bits) − 1

  int saturation_level() const { return (1 << bits) - 1; }
};

}  // namespace rangecal
