#pragma once
// A video as frames, decoded with cv::VideoCapture (FFmpeg first): frame k is the 0-based frame
// index. A video carries no UTC, so its frames are always timed by a timestamps CSV; use a lossless
// codec such as FFV1 for science.
#include <memory>
#include <string>

#include "gnss/formats/file_facts.hpp"
#include "vision/frames/frame_container.hpp"

namespace rangecal {

/// Opens a video; throws rangecal::Error (input) whose message is "missing video file '<path>'"
/// or "cannot open video '<path>'".
std::unique_ptr<FrameContainer> open_video_frames(const std::string& path);

/// `rangecal inspect`: what OpenCV reads: size, frame count, frame rate, codec (no time).
FileFacts video_file_facts(const std::string& path);

}  // namespace rangecal
