// The frame format table: every extension selects exactly one format, a name of no format is
// refused by the frame source with the message it has always had, and the entries hold together
// (what a new entry must fill in is checked here, not only by the formats' own tests).
#include "vision/frames/frame_formats.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <set>
#include <sstream>

#include "config/error.hpp"
#include "support/paths.hpp"
#include "vision/frames/frame_source.hpp"

namespace fs = std::filesystem;
using namespace rangecal;

namespace {

std::vector<std::string> words(const char* list) {
  std::istringstream in(list);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::toupper(c); });
  return s;
}

}  // namespace

TEST(FrameFormats, EachExtensionSelectsExactlyOneFormat) {
  std::map<std::string, std::vector<std::string>> owners;  // extension -> formats listing it
  std::set<std::string> names;
  for (const FrameFormat& f : frame_formats()) {
    EXPECT_TRUE(names.insert(f.name).second) << "two formats are called " << f.name;
    EXPECT_FALSE(words(f.extensions).empty()) << f.name;
    for (const std::string& ext : words(f.extensions)) owners[ext].push_back(f.name);
    for (const std::string& ext : words(f.companion_extensions)) owners[ext].push_back(f.name);
  }
  for (const auto& [ext, formats] : owners) {
    ASSERT_EQ(formats.size(), 1u) << ext << " is claimed by " << formats.size() << " formats";
    EXPECT_EQ(ext[0], '.') << ext;
    std::string lower = ext;  // (a structured binding cannot be captured in C++17)
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    EXPECT_EQ(ext, lower) << "extensions are listed in lower case";
  }
  // Lookup by extension, in any case, lands on the format that lists it; a companion file (a
  // recording's header) is no frame file of its own.
  for (const FrameFormat& f : frame_formats()) {
    for (const std::string& ext : words(f.extensions)) {
      EXPECT_EQ(find_frame_format("dir/take" + ext), &f) << ext;
      EXPECT_EQ(find_frame_format("dir/TAKE" + upper(ext)), &f) << ext;
      EXPECT_EQ(find_frame_format_or_companion("take" + ext), &f) << ext;
    }
    for (const std::string& ext : words(f.companion_extensions)) {
      EXPECT_EQ(find_frame_format("take" + ext), nullptr) << ext;
      EXPECT_EQ(find_frame_format_or_companion("take" + upper(ext)), &f) << ext;
    }
  }
  EXPECT_EQ(frame_file_kind("a/b.MRAW"), FrameFileKind::mraw);
  EXPECT_EQ(frame_file_kind("a/b.Cine"), FrameFileKind::cine);
  EXPECT_EQ(frame_file_kind("a/b.webm"), FrameFileKind::video);
  EXPECT_EQ(frame_file_kind("a/b.TIF"), FrameFileKind::image);
}

TEST(FrameFormats, UnknownExtensionsAreRefusedWithTheSameMessage) {
  for (const char* p : {"a.jpg", "a.JPEG", "a.bmp", "a", "a.", "a.cih", "a.cihx", "dir.png/a.raw"})
    EXPECT_EQ(find_frame_format(p), FrameFileKind::unknown) << p;
  EXPECT_EQ(supported_frame_files(), ".png .tif .tiff, a video, .cine or .mraw");

  const fs::path dir = test::scratch_dir("frame_formats_unknown");
  test::write_text(dir / "ts.csv", "frame,file,utc\n0,a.jpg,2026-05-01T08:00:00Z\n");
  const std::string csv = (dir / "ts.csv").string();
  for (bool allow_missing : {false, true}) {
    FrameSourceOptions o;
    o.allow_missing = allow_missing;  // a file of no format is refused even when frames may be missing
    try {
      (void)FrameSource::from_timestamps_csv(csv, o);
      ADD_FAILURE() << "a .jpg frame file was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::input);
      EXPECT_EQ(std::string(e.what()), csv + ":2: field 'file': '" + (dir / "a.jpg").string() +
                                           "' is not a supported frame file (.png .tif .tiff, a video, "
                                           ".cine or .mraw)");
    }
  }
}

TEST(FrameFormats, EveryEntryCanBeOpenedInspectedAndSaysHowItIsTimed) {
  for (const FrameFormat& f : frame_formats()) {
    EXPECT_NE(f.open, nullptr) << f.name;
    EXPECT_NE(f.facts, nullptr) << f.name;
    EXPECT_NE(std::string(f.listed_as), "") << f.name;
  }
  // The formats that stand alone, and the time sources run.json records for them.
  std::map<std::string, std::string> alone;
  for (const FrameFormat& f : frame_formats())
    if (f.own_time_source) alone[f.name] = f.own_time_source;
  EXPECT_EQ(alone, (std::map<std::string, std::string>{{".cine", ".cine TIME64 stamps"},
                                                       {".mraw", "mraw header + rate"}}));
  EXPECT_EQ(&frame_format(".cine"), FrameFileKind::cine);
  EXPECT_THROW(frame_format("cine"), std::logic_error);
}
