#include "vision/frames/mraw_frames.hpp"

#include <algorithm>
#include <filesystem>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "vision/frames/photron_cih.hpp"
#include "vision/frames/photron_mraw_reader.hpp"

namespace rangecal {

namespace fs = std::filesystem;

namespace {

class MrawFrames : public FrameContainer {
 public:
  explicit MrawFrames(const std::string& path) : mraw_(path) {}

  std::optional<std::int64_t> frame_count() const override { return mraw_.frame_count(); }

  FrameDecodeProblem decode(std::int64_t frame, int, int, ImageFrame& out) const override {
    if (frame >= mraw_.frame_count()) return {frame_beyond_end(mraw_.path(), frame)};
    try {
      const ImageFrame m = mraw_.read_frame(frame);
      out.image = m.image;
      out.bits = m.bits;
    } catch (const Error& err) {
      return {err.what()};
    }
    return {};
  }

  std::vector<UtcTime> own_times(std::optional<double> clock_utc_offset_h) const override {
    // Photron writes the camera clock's local date and time with no zone (Photron FASTCAM Viewer,
    // .cihx fileInfo/date, time): the offset to UTC must come from the user, never from a guess.
    if (!clock_utc_offset_h)
      throw_input_error(mraw_.header().path, 0, mraw_.header().field(PhotronField::time),
                        "the Photron header time is the camera clock's local time with no time zone; give "
                        "frames.clock_utc_offset_h (camera clock - UTC, hours), or frames.timestamps, a "
                        "frame,file,utc CSV naming the .mraw");
    const PhotronFrameClock clock = photron_frame_clock(mraw_.header(), *clock_utc_offset_h);
    std::vector<UtcTime> times;
    times.reserve(static_cast<std::size_t>(mraw_.frame_count()));  // checked against the file size
    for (std::int64_t k = 0; k < mraw_.frame_count(); ++k) times.push_back(clock.frame_time(k));
    return times;
  }

 private:
  PhotronMrawReader mraw_;
};

std::string mraw_lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

std::string yes_no(std::optional<bool> b) {
  return !b ? "not in header" : (*b ? "yes" : "no");
}

// The .mraw beside a Photron header (same folder and stem, .mraw or .MRAW). Throws rangecal::Error
// (input) naming the header when there is none.
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

}  // namespace

std::unique_ptr<FrameContainer> open_mraw_frames(const std::string& path) {
  return std::make_unique<MrawFrames>(path);
}

FileFacts mraw_file_facts(const std::string& path) {
  const std::string ext = mraw_lower_extension(path);
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

}  // namespace rangecal
