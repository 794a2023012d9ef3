#include "vision/frames/frame_source.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <optional>
#include <vector>

#include "config/error.hpp"
#include "config/physical_ranges.hpp"
#include "vision/frames/cine_reader.hpp"
#include "vision/frames/photron_mraw_reader.hpp"

namespace rangecal {

struct VideoHandle {
  std::mutex mutex;
  cv::VideoCapture capture;
  std::int64_t next_index = 0;  ///< index the next read() returns without seeking
  std::int64_t frame_count = 0;
};

FrameFileKind frame_file_kind(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".png" || ext == ".tif" || ext == ".tiff") return FrameFileKind::image;
  if (ext == ".cine") return FrameFileKind::cine;
  if (ext == ".mraw") return FrameFileKind::mraw;
  static const char* const kVideo[] = {".avi", ".mkv",  ".mp4",  ".mov", ".m4v",
                                       ".mpg", ".mpeg", ".webm", ".wmv"};
  for (const char* v : kVideo)
    if (ext == v) return FrameFileKind::video;
  return FrameFileKind::unknown;
}

namespace {

// Any depth/channel layout OpenCV decodes → single-channel CV_8U or CV_16U.
cv::Mat to_grey(cv::Mat m, int* bits) {
  if (m.empty()) return m;
  if (m.channels() == 3)
    cv::cvtColor(m, m, cv::COLOR_BGR2GRAY);
  else if (m.channels() == 4)
    cv::cvtColor(m, m, cv::COLOR_BGRA2GRAY);
  else if (m.channels() != 1)
    return cv::Mat();
  if (m.depth() == CV_8U) {
    *bits = 8;
    return m;
  }
  if (m.depth() == CV_16U) {
    *bits = 16;
    return m;
  }
  return cv::Mat();  // float/signed images are not camera frames
}

std::uint32_t big_endian_u32(const unsigned char* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
}

// A PNG whose chunk chain (PNG spec §5.3: length, type, data, CRC) does not reach IEND inside the
// file, or whose IHDR declares an image beyond the size limit, is refused before libpng sees it:
// libpng would print "libpng error: …" on the console, and a forged size would allocate gigabytes.
bool png_structure_ok(const std::vector<unsigned char>& b) {
  static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (b.size() < 8 || !std::equal(kSignature, kSignature + 8, b.begin())) return false;
  std::size_t at = 8;
  bool first = true;
  while (at + 12 <= b.size()) {
    const std::uint32_t len = big_endian_u32(&b[at]);
    const std::string type(reinterpret_cast<const char*>(&b[at + 4]), 4);
    if (len > b.size() - at - 12) return false;
    if (first) {
      if (type != "IHDR" || len != 13) return false;
      const std::uint32_t w = big_endian_u32(&b[at + 8]), h = big_endian_u32(&b[at + 12]);
      if (w == 0 || h == 0 || w > std::uint32_t(ranges::kMaxImageSidePx) ||
          h > std::uint32_t(ranges::kMaxImageSidePx))
        return false;
      first = false;
    }
    if (type == "IEND") return true;
    at += 12 + std::size_t(len);
  }
  return false;
}

std::uint16_t tiff_u16(const unsigned char* p, bool little) {
  return little ? std::uint16_t(p[0] | (p[1] << 8)) : std::uint16_t((p[0] << 8) | p[1]);
}

std::uint32_t tiff_u32(const unsigned char* p, bool little) {
  return little
             ? (std::uint32_t(p[3]) << 24) | (std::uint32_t(p[2]) << 16) | (std::uint32_t(p[1]) << 8) | p[0]
             : big_endian_u32(p);
}

// ImageWidth (256) and ImageLength (257) of a TIFF's first IFD (TIFF 6.0 §2: 8-byte header, then
// IFD entries of tag, type, count, value; SHORT values sit in the first two bytes of the field).
std::optional<cv::Size> tiff_header_size(const std::vector<unsigned char>& b) {
  if (b.size() < 8) return std::nullopt;
  const bool little = b[0] == 'I' && b[1] == 'I' && b[2] == 42 && b[3] == 0;
  const bool big = b[0] == 'M' && b[1] == 'M' && b[2] == 0 && b[3] == 42;
  if (!little && !big) return std::nullopt;
  const std::uint32_t ifd = tiff_u32(&b[4], little);
  if (ifd > b.size() || b.size() - ifd < 2) return std::nullopt;
  const std::uint16_t n = tiff_u16(&b[ifd], little);
  std::int64_t w = -1, h = -1;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::size_t at = std::size_t(ifd) + 2 + 12 * std::size_t(i);
    if (at + 12 > b.size()) return std::nullopt;
    const std::uint16_t tag = tiff_u16(&b[at], little), type = tiff_u16(&b[at + 2], little);
    if (tag != 256 && tag != 257) continue;
    const std::int64_t v = type == 3 ? tiff_u16(&b[at + 8], little) : tiff_u32(&b[at + 8], little);
    (tag == 256 ? w : h) = v;
  }
  if (w < 0 || h < 0) return std::nullopt;
  return cv::Size(static_cast<int>(std::min<std::int64_t>(w, INT32_MAX)),
                  static_cast<int>(std::min<std::int64_t>(h, INT32_MAX)));
}

std::vector<unsigned char> read_file_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return {};
  f.seekg(0, std::ios::end);
  const std::streamoff size = f.tellg();
  if (size <= 0) return {};
  f.seekg(0);
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
  if (!f.read(reinterpret_cast<char*>(bytes.data()), size)) return {};
  return bytes;
}

}  // namespace

std::optional<cv::Size> image_header_size(const std::vector<unsigned char>& bytes) {
  if (bytes.size() >= 24 && bytes[0] == 0x89 && bytes[1] == 'P' && bytes[12] == 'I' && bytes[13] == 'H')
    return cv::Size(static_cast<int>(std::min<std::uint32_t>(big_endian_u32(&bytes[16]), INT32_MAX)),
                    static_cast<int>(std::min<std::uint32_t>(big_endian_u32(&bytes[20]), INT32_MAX)));
  return tiff_header_size(bytes);
}

cv::Mat decode_image_bytes(const std::vector<unsigned char>& bytes, int* bits) {
  if (bytes.empty()) return cv::Mat();
  if (bytes.size() >= 8 && bytes[0] == 0x89 && !png_structure_ok(bytes)) return cv::Mat();
  return to_grey(cv::imdecode(bytes, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR), bits);
}

cv::Mat decode_image_file(const std::string& path, int* bits) {
  return decode_image_bytes(read_file_bytes(path), bits);
}

FrameSource::FrameSource(FrameSource&&) noexcept = default;
FrameSource& FrameSource::operator=(FrameSource&&) noexcept = default;
FrameSource::~FrameSource() = default;

FrameSource FrameSource::from_timestamps_csv(const std::string& csv_path, const FrameSourceOptions& options) {
  FrameSource s;
  s.origin_ = csv_path;
  s.time_source_ = kTimeSourceCsv;
  s.entries_ = read_frame_timestamps(csv_path).entries;
  s.sensor_w_ = options.width_px;
  s.sensor_h_ = options.height_px;
  s.allow_missing_ = options.allow_missing;
  for (const FrameTimestamp& e : s.entries_) {
    const FrameFileKind kind = frame_file_kind(e.file);
    if (kind == FrameFileKind::unknown)
      throw_input_error(
          csv_path, e.line, "file",
          "'" + e.file + "' is not a supported frame file (.png .tif .tiff, a video, .cine or .mraw)");
    if (kind == FrameFileKind::image || s.container_errors_.count(e.file)) continue;
    std::string problem;
    if (kind == FrameFileKind::cine && !s.cines_.count(e.file)) {
      try {
        s.cines_[e.file] = std::make_shared<CineReader>(e.file);
      } catch (const Error& err) {
        problem = err.what();
      }
    } else if (kind == FrameFileKind::mraw && !s.mraws_.count(e.file)) {
      try {
        s.mraws_[e.file] = std::make_shared<PhotronMrawReader>(e.file);
      } catch (const Error& err) {
        problem = err.what();
      }
    } else if (kind == FrameFileKind::video && !s.videos_.count(e.file)) {
      auto v = std::make_shared<VideoHandle>();
      if (!std::filesystem::exists(e.file))
        problem = "missing video file '" + e.file + "'";
      else if (!v->capture.open(e.file, cv::CAP_FFMPEG) && !v->capture.open(e.file))
        problem = "cannot open video '" + e.file + "'";
      else {
        v->frame_count = static_cast<std::int64_t>(v->capture.get(cv::CAP_PROP_FRAME_COUNT));
        s.videos_[e.file] = v;
      }
    }
    if (!problem.empty()) {
      if (!options.allow_missing) throw_input_error(csv_path, e.line, "file", problem);
      s.container_errors_[e.file] = problem;
      continue;
    }
    std::int64_t n = -1;
    if (kind == FrameFileKind::cine) n = static_cast<std::int64_t>(s.cines_.at(e.file)->frame_count());
    if (kind == FrameFileKind::video) n = s.videos_.at(e.file)->frame_count;
    if (kind == FrameFileKind::mraw) n = s.mraws_.at(e.file)->frame_count();
    if (n >= 0 && e.frame >= n && !options.allow_missing)
      throw_input_error(csv_path, e.line, "frame",
                        "frame " + std::to_string(e.frame) + " is beyond the end of '" + e.file + "' (" +
                            std::to_string(n) + " frames)");
  }
  return s;
}

FrameSource FrameSource::from_cine(const std::string& cine_path, const FrameSourceOptions& options) {
  FrameSource s;
  s.origin_ = cine_path;
  s.time_source_ = kTimeSourceCine;
  s.sensor_w_ = options.width_px;
  s.sensor_h_ = options.height_px;
  auto reader = std::make_shared<CineReader>(cine_path);
  if (!reader->has_times())
    throw_input_error(cine_path, 0, "tagged block 1002 (TimeOnly)",
                      "the .cine has no per-frame time stamps; give a timestamps CSV instead");
  for (std::size_t i = 0; i < reader->frame_count(); ++i) {
    FrameTimestamp e;
    e.frame = static_cast<std::int64_t>(i);
    e.file = cine_path;
    e.utc = reader->frame_time(i);
    if (!s.entries_.empty() && e.utc <= s.entries_.back().utc)
      throw_input_error(cine_path, 0, "time stamp of image " + std::to_string(i),
                        format_iso8601_utc(e.utc) + " is not after the previous image's " +
                            format_iso8601_utc(s.entries_.back().utc));
    s.entries_.push_back(e);
  }
  s.cines_[cine_path] = std::move(reader);
  return s;
}

FrameSource FrameSource::from_mraw(const std::string& mraw_path, const FrameSourceOptions& options,
                                   std::optional<double> clock_utc_offset_h) {
  FrameSource s;
  s.origin_ = mraw_path;
  s.time_source_ = kTimeSourceMrawHeader;
  s.sensor_w_ = options.width_px;
  s.sensor_h_ = options.height_px;
  auto reader = std::make_shared<PhotronMrawReader>(mraw_path);
  // Photron writes the camera clock's local date and time with no zone (Photron FASTCAM Viewer,
  // .cihx fileInfo/date, time): the offset to UTC must come from the user, never from a guess.
  if (!clock_utc_offset_h)
    throw_input_error(reader->header().path, 0, reader->header().field(PhotronField::time),
                      "the Photron header time is the camera clock's local time with no time zone; give "
                      "frames.clock_utc_offset_h (camera clock - UTC, hours), or frames.timestamps, a "
                      "frame,file,utc CSV naming the .mraw");
  const PhotronFrameClock clock = photron_frame_clock(reader->header(), *clock_utc_offset_h);
  s.entries_.reserve(static_cast<std::size_t>(reader->frame_count()));  // checked against the file size
  for (std::int64_t k = 0; k < reader->frame_count(); ++k) {
    FrameTimestamp e;
    e.frame = k;
    e.file = mraw_path;
    e.utc = clock.frame_time(k);
    s.entries_.push_back(e);
  }
  s.mraws_[mraw_path] = std::move(reader);
  return s;
}

namespace {

std::string size_mismatch(const FrameTimestamp& e, int w, int h, const std::string& how, int sensor_w,
                          int sensor_h) {
  return "frame '" + e.file + "' (frame " + std::to_string(e.frame) + ") is " + std::to_string(w) + "x" +
         std::to_string(h) + " px" + how + "; the sensor is " + std::to_string(sensor_w) + "x" +
         std::to_string(sensor_h);
}

// A PNG/TIFF frame file into f; returns the problem ("" when decoded). The header's size is checked
// before decoding: a CSV that lists a forged 30,000-pixel image a thousand times must cost a thousand
// header reads, not a thousand 2 GB decodes.
std::string load_image_file(const FrameTimestamp& e, const std::string& origin, int sensor_w, int sensor_h,
                            ImageFrame& f) {
  if (!std::filesystem::exists(e.file)) return "missing frame file '" + e.file + "'";
  const std::vector<unsigned char> bytes = read_file_bytes(e.file);
  const std::optional<cv::Size> declared = image_header_size(bytes);
  if (declared && sensor_w > 0 && sensor_h > 0 &&
      (declared->width != sensor_w || declared->height != sensor_h))
    throw_input_error(
        origin, e.line, "file",
        size_mismatch(e, declared->width, declared->height, " by its header", sensor_w, sensor_h));
  f.image = decode_image_bytes(bytes, &f.bits);
  if (f.image.empty()) return "cannot decode frame file '" + e.file + "' as an 8/16-bit PNG or TIFF";
  return "";
}

// The open container of e.file, or nullptr with *problem set (its open error, or "not open").
template <typename Handle>
Handle* container_of(const std::map<std::string, std::shared_ptr<Handle>>& open,
                     const std::map<std::string, std::string>& container_errors, const FrameTimestamp& e,
                     std::string* problem) {
  const auto it = open.find(e.file);
  if (it != open.end()) return it->second.get();
  *problem = container_errors.count(e.file) ? container_errors.at(e.file) : "'" + e.file + "' not open";
  return nullptr;
}

std::string beyond_end(const FrameTimestamp& e) {
  return "frame " + std::to_string(e.frame) + " is beyond the end of '" + e.file + "'";
}

std::string load_cine_frame(const CineReader& cine, const FrameTimestamp& e, ImageFrame& f) {
  if (e.frame >= static_cast<std::int64_t>(cine.frame_count())) return beyond_end(e);
  try {
    f.image = cine.read_image(static_cast<std::size_t>(e.frame));
    f.bits = cine.bits();
  } catch (const Error& err) {
    return err.what();
  }
  return "";
}

std::string load_mraw_frame(const PhotronMrawReader& mraw, const FrameTimestamp& e, ImageFrame& f) {
  if (e.frame >= mraw.frame_count()) return beyond_end(e);
  try {
    const ImageFrame m = mraw.read_frame(e.frame);
    f.image = m.image;
    f.bits = m.bits;
  } catch (const Error& err) {
    return err.what();
  }
  return "";
}

// Sequential reads need no seek; the handle remembers where the decoder stands.
std::string load_video_frame(VideoHandle& v, const FrameTimestamp& e, ImageFrame& f) {
  cv::Mat m;
  {
    std::lock_guard<std::mutex> lock(v.mutex);
    if (e.frame != v.next_index) v.capture.set(cv::CAP_PROP_POS_FRAMES, static_cast<double>(e.frame));
    const bool ok = v.capture.read(m);
    v.next_index = ok ? e.frame + 1 : -1;
  }
  f.image = to_grey(m, &f.bits);
  if (f.image.empty()) return "cannot decode frame " + std::to_string(e.frame) + " of video '" + e.file + "'";
  return "";
}

}  // namespace

std::optional<ImageFrame> FrameSource::load(std::size_t i, std::string* skip_reason) const {
  const FrameTimestamp& e = entries_.at(i);
  ImageFrame f;
  f.frame = e.frame;
  f.utc = e.utc;
  std::string problem;
  switch (frame_file_kind(e.file)) {
    case FrameFileKind::image:
      problem = load_image_file(e, origin_, sensor_w_, sensor_h_, f);
      break;
    case FrameFileKind::cine:
      if (const CineReader* c = container_of(cines_, container_errors_, e, &problem))
        problem = load_cine_frame(*c, e, f);
      break;
    case FrameFileKind::mraw:
      if (const PhotronMrawReader* m = container_of(mraws_, container_errors_, e, &problem))
        problem = load_mraw_frame(*m, e, f);
      break;
    case FrameFileKind::video:
      if (VideoHandle* v = container_of(videos_, container_errors_, e, &problem))
        problem = load_video_frame(*v, e, f);
      break;
    case FrameFileKind::unknown:
      problem = "'" + e.file + "' is not a supported frame file";
      break;
  }
  if (!problem.empty()) {
    if (allow_missing_) {
      if (skip_reason) *skip_reason = problem;
      return std::nullopt;
    }
    throw_input_error(origin_, e.line, "file", problem);
  }
  if ((sensor_w_ > 0 && f.image.cols != sensor_w_) || (sensor_h_ > 0 && f.image.rows != sensor_h_))
    throw_input_error(origin_, e.line, "file",
                      size_mismatch(e, f.image.cols, f.image.rows, "", sensor_w_, sensor_h_));
  return f;
}

}  // namespace rangecal
