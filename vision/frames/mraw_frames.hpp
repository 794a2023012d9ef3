#pragma once
// A Photron FASTCAM .mraw as frames (read by photron_mraw_reader.hpp, its .cihx/.cih header
// beside it): frame k is the k-th frame in the file, timed from the header's camera clock, record
// rate, start frame and save step when the camera clock's offset from UTC is given.
#include <memory>
#include <string>

#include "gnss/formats/file_facts.hpp"
#include "vision/frames/frame_container.hpp"

namespace rangecal {

/// Opens a .mraw with the header beside it; throws rangecal::Error (input) as PhotronMrawReader.
std::unique_ptr<FrameContainer> open_mraw_frames(const std::string& path);

/// `rangecal inspect`: size, stored and effective bits, record rate and save step, header clock.
/// `path` is the .mraw or its .cihx/.cih: the other is found beside it (same folder and stem).
FileFacts mraw_file_facts(const std::string& path);

}  // namespace rangecal
