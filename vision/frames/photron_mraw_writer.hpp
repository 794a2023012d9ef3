#pragma once
// Writes Photron recordings: the frames as a .mraw (back to back, layouts as in
// photron_mraw_reader.hpp) and a .cihx beside it (same stem) with the fields photron_cih reads.
// Used by the tests and usable by the simulator. The .cihx is a one-line text preamble followed by
// the XML document; PFV's binary directory after the preamble is not written, so the pair is for
// rangecal and for readers that locate the <cih> document by its text.
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "vision/frames/photron_cih.hpp"

namespace rangecal {

struct PhotronWriteOptions {
  /// Pixel storage: 8 (CV_8UC1 input), 12 (packed) or 16 (CV_16UC1 input).
  int storage_bits = 16;
  /// Significant bits of the input values (they must be < 2^effective_depth); 0 = storage_bits.
  int effective_depth = 0;
  /// Higher: values are written shifted left by storage_bits − effective_depth (the reader shifts
  /// them back); Lower: written as they are.
  EffectiveBitSide effective_side = EffectiveBitSide::lower;
  double record_rate_fps = 0;       ///< recordInfo/recordRate; 0 = not written
  std::int64_t start_frame = 0;     ///< frameInfo/startFrame (camera frame of saved frame 0; 0 = trigger)
  std::int64_t skip_frame = 1;      ///< frameInfo/skipFrame (save step)
  double shutter_s = 0;             ///< recordInfo/shutterSpeedNsec (rounded to ns); 0 = not written
  std::string date;                 ///< fileInfo/date, camera clock "Y/M/D"; "" = not written
  std::string time;                 ///< fileInfo/time, camera clock "h:m:s"; "" = not written
  std::string color_type = "Mono";  ///< imageDataInfo/colorInfo/type
  std::string device_name;          ///< deviceInfo/deviceName; "" = not written
  bool irig = false;                ///< deviceInfo/irig
};

/// Writes `images` (all the same size and type per options.storage_bits) to `mraw_path` and the
/// header to the same path with extension .cihx, each atomically; returns the header's path.
/// Throws rangecal::Error (input) naming the path when there is no image, the images differ in
/// size or type, a value does not fit the effective bits, a 12-bit frame has an odd pixel count,
/// a text field would not be plain text, or writing fails.
std::string write_photron_mraw(const std::string& mraw_path, const std::vector<cv::Mat>& images,
                               const PhotronWriteOptions& options);

}  // namespace rangecal
