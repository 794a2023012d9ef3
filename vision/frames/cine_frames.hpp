#pragma once
// A Phantom .cine as frames (Vision Research; read by cine_reader.hpp): frame k is the k-th saved
// image, timed by the file's own TIME64 stamps when it carries them (tagged block 1002).
#include <memory>
#include <string>
#include <string_view>

#include "gnss/formats/file_facts.hpp"
#include "vision/frames/frame_container.hpp"

namespace rangecal {

/// Opens a .cine; throws rangecal::Error (input) naming it as CineReader does.
std::unique_ptr<FrameContainer> open_cine_frames(const std::string& path);

/// True when a file's first bytes are a .cine's file header ("CI", header size 44).
bool is_cine_head(std::string_view head);

/// `rangecal inspect`: size, bit depth, frame rate, TIME64 stamps on UTC, IRIG flags, trigger time.
FileFacts cine_file_facts(const std::string& path);

}  // namespace rangecal
