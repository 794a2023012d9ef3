#include "vision/frames/video_frames.hpp"

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <opencv2/videoio.hpp>

#include "config/error.hpp"
#include "vision/frames/image_decoding.hpp"

namespace rangecal {

namespace fs = std::filesystem;

namespace {

// The decoder keeps a position: frames are decoded one at a time under the container's lock, and
// sequential reads need no seek.
class VideoFrames : public FrameContainer {
 public:
  explicit VideoFrames(const std::string& path) : path_(path) {
    if (!fs::exists(path)) throw Error(ErrorKind::input, "", 0, "", "missing video file '" + path + "'");
    if (!capture_.open(path, cv::CAP_FFMPEG) && !capture_.open(path))
      throw Error(ErrorKind::input, "", 0, "", "cannot open video '" + path + "'");
    frame_count_ = static_cast<std::int64_t>(capture_.get(cv::CAP_PROP_FRAME_COUNT));
  }

  // A backend that cannot count frames answers a negative count: no bound then.
  std::optional<std::int64_t> frame_count() const override {
    if (frame_count_ < 0) return std::nullopt;
    return frame_count_;
  }

  FrameDecodeProblem decode(std::int64_t frame, int, int, ImageFrame& out) const override {
    cv::Mat m;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (frame != next_index_) capture_.set(cv::CAP_PROP_POS_FRAMES, static_cast<double>(frame));
      const bool ok = capture_.read(m);
      next_index_ = ok ? frame + 1 : -1;
    }
    out.image = to_grey_frame(m, &out.bits);
    if (out.image.empty())
      return {"cannot decode frame " + std::to_string(frame) + " of video '" + path_ + "'"};
    return {};
  }

 private:
  std::string path_;
  mutable std::mutex mutex_;
  mutable cv::VideoCapture capture_;
  mutable std::int64_t next_index_ = 0;  ///< index the next read() returns without seeking
  std::int64_t frame_count_ = 0;
};

}  // namespace

std::unique_ptr<FrameContainer> open_video_frames(const std::string& path) {
  return std::make_unique<VideoFrames>(path);
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

}  // namespace rangecal
