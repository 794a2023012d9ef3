#include "vision/frames/frame_timestamps_facts.hpp"

#include <filesystem>
#include <map>
#include <set>

#include "vision/frames/frame_formats.hpp"
#include "vision/frames/frame_timestamps_reader.hpp"

namespace rangecal {

namespace fs = std::filesystem;

FileFacts frame_timestamps_file_facts(const std::string& path) {
  const FrameTimestamps ts = read_frame_timestamps(path);
  FileFacts f;
  f.path = path;
  f.kind = "frame timestamps CSV";
  f.size_bytes = file_size_bytes(path);
  f.time_system = "UTC (ISO 8601 with Z)";
  std::vector<UtcTime> t;
  std::set<std::string> files;
  std::map<std::string, std::uint64_t> by_kind;
  for (const FrameTimestamp& e : ts.entries) {
    t.push_back(e.utc);
    if (files.insert(e.file).second) {
      const FrameFormat* format = find_frame_format(e.file);
      ++by_kind[format ? format->name : "unsupported"];
    }
  }
  if (!t.empty()) f.utc = UtcSpan{t.front(), t.back()};
  f.rate_hz = median_rate_hz(t);
  if (f.rate_hz) f.rate_source = "median interval";
  std::uint64_t missing = 0;
  for (const std::string& file : files) {
    std::error_code ec;
    if (!fs::exists(file, ec)) ++missing;
  }
  f.counts.emplace_back("frames", ts.entries.size());
  f.counts.emplace_back("frame files", files.size());
  for (const auto& [kind, n] : by_kind) f.counts.emplace_back("frame files (" + kind + ")", n);
  f.counts.emplace_back("frame files missing", missing);
  if (missing > 0)
    f.notes.push_back(std::to_string(missing) + " frame file(s) named in the CSV do not exist");
  return f;
}

}  // namespace rangecal
