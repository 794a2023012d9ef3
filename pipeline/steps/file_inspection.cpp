#include "pipeline/steps/file_inspection.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/text_encoding.hpp"
#include "gnss/formats/ardupilot_dataflash.hpp"
#include "gnss/formats/gnss_file_facts.hpp"
#include "vision/frames/frame_formats.hpp"
#include "vision/frames/frame_timestamps_facts.hpp"

namespace rangecal {

namespace fs = std::filesystem;

namespace {

// Enough for any header line of our text formats and every magic number.
constexpr std::size_t kHeadBytes = 64 * 1024;

std::string read_head(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw_input_error(path, 0, "", "no such file");
  if (!fs::is_regular_file(path, ec)) throw_input_error(path, 0, "", "not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw_input_error(path, 0, "", "cannot open the file for reading");
  std::string head(kHeadBytes, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head;
}

bool has_control_bytes(std::string_view head) {
  for (char c : head)
    if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r') return true;
  return false;
}

// The first line that is not blank and not a '#' comment (as CsvTable skips them).
std::string first_text_line(std::string_view head) {
  head = strip_utf8_bom(head);
  std::size_t at = 0;
  while (at < head.size()) {
    const std::size_t end = std::min(head.find('\n', at), head.size());
    const std::string_view line = trim(head.substr(at, end - at));
    if (!line.empty() && line[0] != '#') return std::string(line);
    at = end + 1;
  }
  return "";
}

bool header_is(const std::vector<std::string>& cols, std::initializer_list<const char*> want) {
  std::set<std::string> have(cols.begin(), cols.end());
  for (const char* w : want)
    if (!have.count(w)) return false;
  return true;
}

[[noreturn]] void unknown_kind(const std::string& path, const std::string& why) {
  throw_input_error(path, 0, "",
                    "not a kind of file rangecal reads: " + why +
                        " (known: RTKLIB .pos, PX4 .ulg, ArduPilot .bin, Phantom .cine, Photron "
                        ".mraw/.cihx/.cih, frame timestamps / attitude / lamp track / pole survey / pole "
                        "picks CSV, video, PNG/TIFF image)");
}

}  // namespace

const char* to_string(InputFileKind k) {
  switch (k) {
    case InputFileKind::rtklib_pos:
      return "rtklib_pos";
    case InputFileKind::px4_ulog:
      return "px4_ulog";
    case InputFileKind::ardupilot_dataflash:
      return "ardupilot_dataflash";
    case InputFileKind::phantom_cine:
      return "phantom_cine";
    case InputFileKind::photron_mraw:
      return "photron_mraw";
    case InputFileKind::frame_timestamps_csv:
      return "frame_timestamps_csv";
    case InputFileKind::attitude_csv:
      return "attitude_csv";
    case InputFileKind::lamp_track_csv:
      return "lamp_track_csv";
    case InputFileKind::pole_survey_csv:
      return "pole_survey_csv";
    case InputFileKind::pole_picks_csv:
      return "pole_picks_csv";
    case InputFileKind::video:
      return "video";
    case InputFileKind::image:
      return "image";
    case InputFileKind::other_frame_format:
      return "other_frame_format";
  }
  return "unknown";
}

namespace {

// The kind of the built-in frame formats that have one; any other registered format is
// other_frame_format.
InputFileKind frame_input_kind(const FrameFormat* format) {
  if (format == FrameFileKind::cine) return InputFileKind::phantom_cine;
  if (format == FrameFileKind::mraw) return InputFileKind::photron_mraw;
  if (format == FrameFileKind::video) return InputFileKind::video;
  if (format == FrameFileKind::image) return InputFileKind::image;
  return InputFileKind::other_frame_format;
}

struct Classified {
  InputFileKind kind;
  const FrameFormat* frame_format = nullptr;  ///< for the frame kinds: whose facts to read
};

Classified classify(const std::string& path) {
  const std::string head = read_head(path);
  // A .mraw is bare pixels: only its name says what it is.
  const FrameFormat* named = find_frame_format_or_companion(path);
  if (named && named->bare) return {frame_input_kind(named), named};
  if (head.empty()) throw_input_error(path, 0, "", "the file is empty");
  if (head.compare(0, 4, "ULog") == 0) return {InputFileKind::px4_ulog};
  if (is_dataflash(head)) return {InputFileKind::ardupilot_dataflash};
  for (const FrameFormat& f : frame_formats())
    if (f.magic && f.magic(head)) return {frame_input_kind(&f), &f};
  if (named) return {frame_input_kind(named), named};
  if (has_control_bytes(head)) unknown_kind(path, "a binary file with no known magic bytes");
  const std::string line = first_text_line(head);
  if (line.empty()) unknown_kind(path, "a text file with no header line");
  if (line[0] == '%') return {InputFileKind::rtklib_pos};
  const std::vector<std::string> cols = split_trim(line, ',');
  if (header_is(cols, {"frame", "file", "utc"})) return {InputFileKind::frame_timestamps_csv};
  if (header_is(cols, {"utc", "roll_deg", "pitch_deg", "yaw_deg"})) return {InputFileKind::attitude_csv};
  if (header_is(cols, {"utc", "E", "N", "U", "quality"})) return {InputFileKind::lamp_track_csv};
  if (header_is(cols, {"id", "role"})) return {InputFileKind::pole_survey_csv};
  if (header_is(cols, {"id", "u", "v"})) return {InputFileKind::pole_picks_csv};
  unknown_kind(path, "a text file whose first line '" + printable_text(line.substr(0, 80)) +
                         "' is no header rangecal knows");
}

}  // namespace

InputFileKind input_file_kind(const std::string& path) {
  return classify(path).kind;
}

FileFacts inspect_input_file(const std::string& path) {
  const Classified c = classify(path);
  if (c.frame_format) return c.frame_format->facts(path);
  switch (c.kind) {
    case InputFileKind::rtklib_pos:
      return pos_file_facts(path);
    case InputFileKind::px4_ulog:
      return ulog_file_facts(path);
    case InputFileKind::ardupilot_dataflash:
      return dataflash_file_facts(path);
    case InputFileKind::frame_timestamps_csv:
      return frame_timestamps_file_facts(path);
    case InputFileKind::attitude_csv:
      return attitude_csv_file_facts(path);
    case InputFileKind::lamp_track_csv:
      return lamp_track_file_facts(path);
    case InputFileKind::pole_survey_csv:
      return pole_survey_file_facts(path);
    case InputFileKind::pole_picks_csv:
      return pole_picks_file_facts(path);
    case InputFileKind::phantom_cine:
    case InputFileKind::photron_mraw:
    case InputFileKind::video:
    case InputFileKind::image:
    case InputFileKind::other_frame_format:
      break;  // read by their frame format, above
  }
  unknown_kind(path, "no reader");
}

std::vector<std::string> distinct_recordings(const std::vector<std::string>& paths) {
  std::vector<std::string> out;
  std::set<std::string> seen;
  for (const std::string& p : paths) {
    // A recording of several files (a Photron .mraw with its header) is one entry, whichever file
    // names it.
    const FrameFormat* format = find_frame_format_or_companion(p);
    fs::path key(p);
    if (format && format->companion_extensions[0] != '\0') key.replace_extension("");
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(key, ec);
    if (seen.insert((ec ? key : canonical).string()).second) out.push_back(p);
  }
  return out;
}

std::vector<FileSpanComparison> compare_file_spans(const std::vector<FileFacts>& files) {
  std::vector<FileSpanComparison> out;
  for (std::size_t a = 0; a < files.size(); ++a)
    for (std::size_t b = a + 1; b < files.size(); ++b)
      if (files[a].utc && files[b].utc) out.push_back({a, b, compare_spans(*files[a].utc, *files[b].utc)});
  return out;
}

}  // namespace rangecal
