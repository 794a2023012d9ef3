#include "vision/frames/frame_timestamps_reader.hpp"

#include <filesystem>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "gnss/time/csv_utc.hpp"

namespace rangecal {

FrameTimestamps parse_frame_timestamps(const std::string& text, const std::string& csv_path) {
  const CsvTable t = parse_csv(text, csv_path);
  const std::size_t c_frame = t.column("frame");
  const std::size_t c_file = t.column("file");
  const std::size_t c_utc = t.column("utc");
  const std::filesystem::path folder = std::filesystem::path(csv_path).parent_path();
  FrameTimestamps out;
  out.csv_path = csv_path;
  out.entries.reserve(t.records.size());
  for (const CsvRecord& r : t.records) {
    FrameTimestamp e;
    e.line = r.line;
    e.frame = t.integer(r, c_frame);
    if (e.frame < 0)
      throw_input_error(csv_path, r.line, "frame", "negative frame number " + std::to_string(e.frame));
    const std::string& file = t.text(r, c_file);
    if (file.empty()) throw_input_error(csv_path, r.line, "file", "empty file name");
    const std::filesystem::path fp(file);
    e.file = (fp.is_absolute() ? fp : folder / fp).lexically_normal().string();
    e.utc = csv_utc(t, r, c_utc);
    if (!out.entries.empty()) {
      const FrameTimestamp& prev = out.entries.back();
      if (e.utc <= prev.utc)
        throw_input_error(csv_path, r.line, "utc",
                          "time " + format_iso8601_utc(e.utc) + " is not after line " +
                              std::to_string(prev.line) + "'s " + format_iso8601_utc(prev.utc) +
                              " (frames must be in time order)");
      if (e.frame <= prev.frame)
        throw_input_error(csv_path, r.line, "frame",
                          "frame " + std::to_string(e.frame) + " is not after line " +
                              std::to_string(prev.line) + "'s frame " + std::to_string(prev.frame));
    }
    out.entries.push_back(std::move(e));
  }
  return out;
}

FrameTimestamps read_frame_timestamps(const std::string& csv_path) {
  return parse_frame_timestamps(read_file_text(csv_path), csv_path);
}

}  // namespace rangecal
