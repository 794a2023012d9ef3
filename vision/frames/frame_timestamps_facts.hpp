#pragma once
// FileFacts (gnss/formats/file_facts.hpp) of a frame timestamps CSV, read with the reader the
// frame source uses: frames, UTC span, rate, frame files referenced (by format) and missing. Each
// frame format's own facts are in its file, listed in frame_formats.hpp. Throws rangecal::Error
// (input) naming the file as the reader does.
#include <string>

#include "gnss/formats/file_facts.hpp"

namespace rangecal {

FileFacts frame_timestamps_file_facts(const std::string& path);

}  // namespace rangecal
