#include "vision/frames/cine_frames.hpp"

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "vision/frames/cine_reader.hpp"

namespace rangecal {

namespace {

class CineFrames : public FrameContainer {
 public:
  explicit CineFrames(const std::string& path) : cine_(path) {}

  std::optional<std::int64_t> frame_count() const override {
    return static_cast<std::int64_t>(cine_.frame_count());
  }

  FrameDecodeProblem decode(std::int64_t frame, int, int, ImageFrame& out) const override {
    if (frame >= static_cast<std::int64_t>(cine_.frame_count()))
      return {frame_beyond_end(cine_.path(), frame)};
    try {
      out.image = cine_.read_image(static_cast<std::size_t>(frame));
      out.bits = cine_.bits();
    } catch (const Error& err) {
      return {err.what()};
    }
    return {};
  }

  std::vector<UtcTime> own_times(std::optional<double>) const override {
    const std::string& path = cine_.path();
    if (!cine_.has_times())
      throw_input_error(path, 0, "tagged block 1002 (TimeOnly)",
                        "the .cine has no per-frame time stamps; give a timestamps CSV instead");
    std::vector<UtcTime> times;
    for (std::size_t i = 0; i < cine_.frame_count(); ++i) {
      const UtcTime t = cine_.frame_time(i);
      if (!times.empty() && t <= times.back())
        throw_input_error(
            path, 0, "time stamp of image " + std::to_string(i),
            format_iso8601_utc(t) + " is not after the previous image's " + format_iso8601_utc(times.back()));
      times.push_back(t);
    }
    return times;
  }

 private:
  CineReader cine_;
};

}  // namespace

std::unique_ptr<FrameContainer> open_cine_frames(const std::string& path) {
  return std::make_unique<CineFrames>(path);
}

bool is_cine_head(std::string_view head) {
  return head.size() >= 4 && head[0] == 'C' && head[1] == 'I' && static_cast<unsigned char>(head[2]) == 44 &&
         head[3] == 0;
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

}  // namespace rangecal
