#pragma once
// The frame formats rangecal reads, as one table (frame_formats.cpp): each entry names the format,
// the extensions that select it, how its files open as FrameContainers, whether it can stand alone
// without a timestamps CSV, and what `rangecal inspect` needs of it. FrameSource and `rangecal
// inspect` look formats up here; a new format is its reader file and one line of the table.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "gnss/formats/file_facts.hpp"
#include "vision/frames/frame_container.hpp"

namespace rangecal {

struct FrameFormat {
  /// Short name, as `rangecal inspect` counts a timestamps CSV's files ("frame files (.cine)").
  const char* name;
  /// The extensions that select the format (lower case, with the dot, space-separated); matched
  /// case-insensitively. Each extension belongs to one format.
  const char* extensions;
  /// How the message refusing an unsupported frame file lists the format.
  const char* listed_as;
  /// Opens a file; throws rangecal::Error (input) naming it when it cannot.
  std::unique_ptr<FrameContainer> (*open)(const std::string& path);
  /// Where the frame times come from when the file stands alone, without a timestamps CSV
  /// (FrameContainer::own_times; FrameSource::time_source()); nullptr when it cannot.
  const char* own_time_source;
  /// `rangecal inspect`: the file's facts, read with the same reader.
  FileFacts (*facts)(const std::string& path);
  /// `rangecal inspect`: whether a file's first bytes are this format's; nullptr when only its
  /// name can say.
  bool (*magic)(std::string_view head);
  /// `rangecal inspect`: the recording's other files (same folder and stem) it also takes for
  /// this format, space-separated, or "" when a file is a recording of its own.
  const char* companion_extensions;
  /// `rangecal inspect`: the file is bare pixels, so its name is trusted before its content is
  /// read at all.
  bool bare;
};

/// Every format, in table order.
const std::vector<FrameFormat>& frame_formats();

/// The format whose extensions hold `path`'s (case-insensitive); nullptr when none does.
const FrameFormat* find_frame_format(const std::string& path);

/// The format called `name`; throws std::logic_error when the table has none (a caller's typo).
const FrameFormat& frame_format(const std::string& name);

/// The formats as the message refusing an unsupported frame file lists them:
/// ".png .tif .tiff, a video, .cine or .mraw".
std::string supported_frame_files();

/// `rangecal inspect`: the format whose extensions or companion extensions hold `path`'s;
/// nullptr when none does.
const FrameFormat* find_frame_format_or_companion(const std::string& path);

/// Handles on the built-in formats, for callers that ask which one a file is
/// (`frame_file_kind(p) == FrameFileKind::mraw`); a new format needs none.
struct FrameFileKind {
  static const FrameFormat* const image;
  static const FrameFormat* const video;
  static const FrameFormat* const cine;
  static const FrameFormat* const mraw;
  static constexpr const FrameFormat* unknown = nullptr;
};
inline const FrameFormat* frame_file_kind(const std::string& path) {
  return find_frame_format(path);
}

}  // namespace rangecal
