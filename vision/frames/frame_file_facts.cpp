#include "vision/frames/frame_file_facts.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <opencv2/videoio.hpp>
#include <set>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "vision/frames/cine_reader.hpp"
#include "vision/frames/frame_source.hpp"
#include "vision/frames/frame_timestamps_reader.hpp"
#include "vision/frames/photron_cih.hpp"
#include "vision/frames/photron_mraw_reader.hpp"

namespace rangecal {

namespace fs = std::filesystem;

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

std::string yes_no(std::optional<bool> b) {
  return !b ? "not in header" : (*b ? "yes" : "no");
}

}  // namespace

std::string find_photron_mraw(const std::string& header_path) {
  for (const char* ext : {".mraw", ".MRAW"}) {
    fs::path c(header_path);
    c.replace_extension(ext);
    std::error_code ec;
    if (fs::is_regular_file(c, ec)) return c.string();
  }
  throw_input_error(header_path, 0, "",
                    "no .mraw beside the Photron header (looked for " +
                        fs::path(header_path).replace_extension(".mraw").filename().string() + ")");
}

FileFacts cine_file_facts(const std::string& path) {
  const CineReader cine(path);
  const CineHeader& h = cine.header();
  FileFacts f;
  f.path = path;
  f.kind = "Phantom .cine";
  f.size_bytes = file_size_bytes(path);
  f.width_px = h.width();
  f.height_px = h.height();
  f.bits = cine.bits();
  if (h.bi_bit_count != cine.bits()) f.stored_bits = h.bi_bit_count;
  if (h.frame_rate > 0) {
    f.rate_hz = h.frame_rate;
    f.rate_source = "header (SETUP.FrameRate)";
  }
  const std::size_t n = cine.frame_count();
  f.counts.emplace_back("frames", n);
  f.counts.emplace_back("frames recorded (TotalImageCount)", h.total_image_count);
  if (cine.has_times() && n > 0) {
    f.time_system = "UTC (TIME64 per frame, tagged block 1002)";
    f.utc = UtcSpan{cine.frame_time(0), cine.frame_time(n - 1)};
    std::uint64_t locked = 0;
    for (std::size_t i = 0; i < n; ++i) locked += cine.frame_irig_locked(i);
    f.counts.emplace_back("frames IRIG-synchronised", locked);
    f.details.emplace_back(
        "IRIG", std::to_string(locked) + " of " + std::to_string(n) + " frame stamps IRIG-synchronised");
  } else {
    f.time_system = "no per-frame time stamps (no tagged block 1002)";
    f.notes.push_back("no frame time stamps: the frames need a timestamps CSV");
  }
  f.details.emplace_back("trigger time",
                         format_iso8601_utc(h.trigger_time, 6) +
                             (h.trigger_irig_locked ? " (IRIG-synchronised)" : " (not IRIG-synchronised)"));
  f.details.emplace_back("first image number", std::to_string(h.first_image_no));
  f.details.emplace_back("compression", std::to_string(h.compression) + " (biCompression " +
                                            std::to_string(h.bi_compression) + ")");
  if (h.real_bpp > 0) f.details.emplace_back("sensor bits (RealBPP)", std::to_string(h.real_bpp));
  if (h.shutter_ns > 0)
    f.details.emplace_back("exposure", format_number("%.3f", h.shutter_ns * 1e-3) + " us");
  return f;
}

FileFacts mraw_file_facts(const std::string& path) {
  const std::string ext = lower_extension(path);
  const bool given_header = ext == ".cih" || ext == ".cihx";
  const std::string mraw = given_header ? find_photron_mraw(path) : path;
  const std::string header_path = given_header ? path : find_photron_header(path);
  const PhotronMrawReader reader(mraw, header_path);
  const PhotronHeader& h = reader.header();
  FileFacts f;
  f.path = mraw;
  f.kind = "Photron .mraw";
  f.size_bytes = file_size_bytes(mraw);
  f.width_px = h.width;
  f.height_px = h.height;
  f.bits = h.effective_depth;
  if (h.color_bit != h.effective_depth) f.stored_bits = h.color_bit;
  const std::int64_t skip = h.skip_frame.value_or(1);
  if (h.record_rate_fps) {
    f.rate_hz = *h.record_rate_fps / static_cast<double>(skip);
    f.rate_source = "header (record rate / save step)";
  }
  f.counts.emplace_back("frames", static_cast<std::uint64_t>(h.total_frame));
  if (h.recorded_frame)
    f.counts.emplace_back("frames recorded", static_cast<std::uint64_t>(*h.recorded_frame));
  f.time_system = "camera clock (header date " +
                  (h.date.empty() ? std::string("absent") : "'" + h.date + "'") + ", time " +
                  (h.time.empty() ? std::string("absent") : "'" + h.time + "'") +
                  "; local time, no zone recorded)";
  try {
    const PhotronFrameClock clock = photron_frame_clock(h, 0.0);
    f.utc = UtcSpan{clock.frame_time(0), clock.frame_time(h.total_frame - 1)};
    f.notes.push_back(
        "the span is the camera clock read as if it were UTC; give the frames a timestamps CSV "
        "or camera.clock_utc_offset_h");
  } catch (const Error& e) {
    f.notes.push_back("no frame times from the header: " + e.reason());
  }
  f.details.emplace_back("header", header_path);
  if (h.record_rate_fps)
    f.details.emplace_back("record rate", format_number("%g", *h.record_rate_fps) + " fps");
  f.details.emplace_back("save step (skipFrame)", std::to_string(skip));
  if (h.start_frame) f.details.emplace_back("start frame", std::to_string(*h.start_frame));
  if (!h.device_name.empty()) f.details.emplace_back("camera", h.device_name);
  f.details.emplace_back("effective bits side",
                         h.effective_side == EffectiveBitSide::lower ? "lower" : "higher");
  f.details.emplace_back("IRIG", yes_no(h.irig));
  f.details.emplace_back("IRIG phase lock", yes_no(h.irig_phase_lock));
  if (h.shutter_s) f.details.emplace_back("exposure", format_number("%.3f", *h.shutter_s * 1e6) + " us");
  return f;
}

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
      switch (frame_file_kind(e.file)) {
        case FrameFileKind::image:
          ++by_kind["image"];
          break;
        case FrameFileKind::video:
          ++by_kind["video"];
          break;
        case FrameFileKind::cine:
          ++by_kind[".cine"];
          break;
        case FrameFileKind::mraw:
          ++by_kind[".mraw"];
          break;
        case FrameFileKind::unknown:
          ++by_kind["unsupported"];
          break;
      }
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

FileFacts video_file_facts(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw_input_error(path, 0, "", "no such file");
  cv::VideoCapture v;
  if (!v.open(path, cv::CAP_FFMPEG) && !v.open(path))
    throw_input_error(path, 0, "", "OpenCV cannot open it as a video");
  FileFacts f;
  f.path = path;
  f.kind = "video";
  f.size_bytes = file_size_bytes(path);
  f.width_px = static_cast<int>(v.get(cv::CAP_PROP_FRAME_WIDTH));
  f.height_px = static_cast<int>(v.get(cv::CAP_PROP_FRAME_HEIGHT));
  f.bits = 8;  // cv::VideoCapture decodes to 8-bit BGR, as the frame source reads it
  const double fps = v.get(cv::CAP_PROP_FPS);
  if (fps > 0) {
    f.rate_hz = fps;
    f.rate_source = "container";
  }
  f.counts.emplace_back("frames", static_cast<std::uint64_t>(std::max(0.0, v.get(cv::CAP_PROP_FRAME_COUNT))));
  const auto fourcc = static_cast<std::uint32_t>(v.get(cv::CAP_PROP_FOURCC));
  std::string codec;
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((fourcc >> (8 * i)) & 0xFF);
    codec += (c >= 0x20 && c < 0x7F) ? c : '?';
  }
  f.details.emplace_back("codec (FourCC)", codec);
  f.time_system = "none (a video carries no UTC: give its frames a timestamps CSV)";
  return f;
}

FileFacts image_file_facts(const std::string& path) {
  int bits = 0;
  const cv::Mat m = decode_image_file(path, &bits);
  if (m.empty()) throw_input_error(path, 0, "", "cannot decode it as an 8/16-bit PNG or TIFF");
  FileFacts f;
  f.path = path;
  f.kind = "image";
  f.size_bytes = file_size_bytes(path);
  f.width_px = m.cols;
  f.height_px = m.rows;
  f.bits = bits;
  f.counts.emplace_back("frames", 1);
  f.time_system = "none (an image carries no UTC: a timestamps CSV gives it one)";
  return f;
}

}  // namespace rangecal
