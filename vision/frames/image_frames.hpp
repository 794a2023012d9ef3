#pragma once
// PNG and TIFF files as frames (decoded by image_decoding.hpp): one frame a file, 8/16-bit grey
// or colour (converted to grey at the same depth). An image carries no UTC, so its frames are
// always timed by a timestamps CSV, whose `frame` number it takes as given.
#include <memory>
#include <string>

#include "gnss/formats/file_facts.hpp"
#include "vision/frames/frame_container.hpp"

namespace rangecal {

/// Reads nothing yet: a timestamps CSV may name thousands of images, each checked when decoded
/// (a missing one is then a missing frame).
std::unique_ptr<FrameContainer> open_image_frames(const std::string& path);

/// `rangecal inspect`: size and bit depth.
FileFacts image_file_facts(const std::string& path);

}  // namespace rangecal
