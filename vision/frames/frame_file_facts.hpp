#pragma once
// FileFacts (gnss/formats/file_facts.hpp) of a camera's frame files, each read with the reader the
// frame source uses, so that what `rangecal inspect` shows is what the stages will read:
//   Phantom .cine        size, bit depth, frame rate, TIME64 stamps on UTC, IRIG flags, trigger time
//   Photron .mraw/.cih(x) size, stored and effective bits, record rate and save step, header clock
//   frame timestamps CSV  frames, UTC span, rate, frame files referenced and missing
//   video                 what OpenCV reads: size, frame count, frame rate, codec (no time)
//   image (PNG, TIFF)     size and bit depth
// Each throws rangecal::Error (input) naming the file as its reader does.
#include <string>

#include "gnss/formats/file_facts.hpp"

namespace rangecal {

FileFacts cine_file_facts(const std::string& path);
/// `path` is the .mraw or its .cihx/.cih: the other is found beside it (same folder and stem).
FileFacts mraw_file_facts(const std::string& path);
FileFacts frame_timestamps_file_facts(const std::string& path);
FileFacts video_file_facts(const std::string& path);
FileFacts image_file_facts(const std::string& path);

/// The .mraw beside a Photron header (same folder and stem, .mraw or .MRAW). Throws
/// rangecal::Error (input) naming the header when there is none.
std::string find_photron_mraw(const std::string& header_path);

}  // namespace rangecal
