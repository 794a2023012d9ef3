#pragma once
// `rangecal inspect`: which kind of input a file is, its facts (FileFacts, gathered by the layer
// that reads the format), and how the time spans of several files relate (docs/cli.md).
//
// The kind is chosen by content where the content says it — magic bytes (ULog, DataFlash, and the
// frame formats that have one, such as .cine), the first line of a text file (a `%` RTKLIB header;
// the header row of each CSV format) — and by extension where it cannot: a Photron .mraw has no
// header of its own (its .cihx/.cih is found beside it, and either may be given), videos and
// images are recognised by extension and opened. What each frame format needs here is in its entry
// of vision/frames/frame_formats.hpp.
#include <string>
#include <vector>

#include "gnss/formats/file_facts.hpp"
#include "gnss/time/span_comparison.hpp"

namespace rangecal {

enum class InputFileKind {
  rtklib_pos,
  px4_ulog,
  ardupilot_dataflash,
  phantom_cine,
  photron_mraw,  ///< the .mraw or its .cihx/.cih
  frame_timestamps_csv,
  attitude_csv,
  lamp_track_csv,
  pole_survey_csv,
  pole_picks_csv,
  video,
  image,
  other_frame_format,  ///< a frame file of a registered format not named above (frame_formats.hpp)
};
const char* to_string(InputFileKind k);

/// The kind of the file at `path`. Throws rangecal::Error (input) naming the file when it is
/// missing or unreadable, or when it is of no kind rangecal reads (the reason says what it looked
/// like).
InputFileKind input_file_kind(const std::string& path);

/// The facts of the file at `path`, read with its kind's reader. Throws rangecal::Error (input) as
/// input_file_kind does and as that reader does.
FileFacts inspect_input_file(const std::string& path);

/// Drops every file after the first that describes the same recording (a .mraw given beside its
/// .cihx), keeping the order.
std::vector<std::string> distinct_recordings(const std::vector<std::string>& paths);

/// The span comparison of file `b` against file `a` (indices into the facts given).
struct FileSpanComparison {
  std::size_t a = 0, b = 0;
  SpanComparison comparison;
};

/// Every pair (a < b) of the files that have a UTC span, in order.
std::vector<FileSpanComparison> compare_file_spans(const std::vector<FileFacts>& files);

}  // namespace rangecal
