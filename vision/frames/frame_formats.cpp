#include "vision/frames/frame_formats.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "vision/frames/cine_frames.hpp"
#include "vision/frames/image_frames.hpp"
#include "vision/frames/mraw_frames.hpp"
#include "vision/frames/video_frames.hpp"

namespace rangecal {

const std::vector<FrameFormat>& frame_formats() {
  // clang-format off
  static const std::vector<FrameFormat> kFormats = {
    // name     extensions                                          listed as          open               own times of a file alone   inspect: facts    magic         companions     bare
    {"image",  ".png .tif .tiff",                                   ".png .tif .tiff", open_image_frames, nullptr,                    image_file_facts, nullptr,      "",            false},
    {"video",  ".avi .mkv .mp4 .mov .m4v .mpg .mpeg .webm .wmv",    "a video",         open_video_frames, nullptr,                    video_file_facts, nullptr,      "",            false},
    {".cine",  ".cine",                                             ".cine",           open_cine_frames,  ".cine TIME64 stamps",      cine_file_facts,  is_cine_head, "",            false},
    {".mraw",  ".mraw",                                             ".mraw",           open_mraw_frames,  "mraw header + rate",       mraw_file_facts,  nullptr,      ".cih .cihx",  true},
  };
  // clang-format on
  return kFormats;
}

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

bool in_list(const std::string& ext, const char* list) {
  if (ext.empty()) return false;
  std::istringstream words(list);
  for (std::string w; words >> w;)
    if (w == ext) return true;
  return false;
}

}  // namespace

const FrameFormat* find_frame_format(const std::string& path) {
  const std::string ext = lower_extension(path);
  for (const FrameFormat& f : frame_formats())
    if (in_list(ext, f.extensions)) return &f;
  return nullptr;
}

const FrameFormat* find_frame_format_or_companion(const std::string& path) {
  const std::string ext = lower_extension(path);
  for (const FrameFormat& f : frame_formats())
    if (in_list(ext, f.extensions) || in_list(ext, f.companion_extensions)) return &f;
  return nullptr;
}

const FrameFormat& frame_format(const std::string& name) {
  for (const FrameFormat& f : frame_formats())
    if (name == f.name) return f;
  throw std::logic_error("no frame format '" + name + "'");
}

std::string supported_frame_files() {
  const std::vector<FrameFormat>& all = frame_formats();
  std::string out;
  for (std::size_t i = 0; i < all.size(); ++i)
    out += (i == 0 ? "" : i + 1 == all.size() ? " or " : ", ") + std::string(all[i].listed_as);
  return out;
}

const FrameFormat* const FrameFileKind::image = &frame_format("image");
const FrameFormat* const FrameFileKind::video = &frame_format("video");
const FrameFormat* const FrameFileKind::cine = &frame_format(".cine");
const FrameFormat* const FrameFileKind::mraw = &frame_format(".mraw");

}  // namespace rangecal
