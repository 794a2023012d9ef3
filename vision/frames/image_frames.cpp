#include "vision/frames/image_frames.hpp"

#include <filesystem>
#include <vector>

#include "config/error.hpp"
#include "vision/frames/image_decoding.hpp"

namespace rangecal {

namespace {

class ImageFrames : public FrameContainer {
 public:
  explicit ImageFrames(const std::string& path) : path_(path) {}

  std::optional<std::int64_t> frame_count() const override { return std::nullopt; }

  // The header's size is checked before decoding: a CSV that lists a forged 30,000-pixel image a
  // thousand times must cost a thousand header reads, not a thousand 2 GB decodes.
  FrameDecodeProblem decode(std::int64_t frame, int sensor_w, int sensor_h, ImageFrame& out) const override {
    if (!std::filesystem::exists(path_)) return {"missing frame file '" + path_ + "'"};
    const std::vector<unsigned char> bytes = read_file_bytes(path_);
    const std::optional<cv::Size> declared = image_header_size(bytes);
    if (declared && sensor_w > 0 && sensor_h > 0 &&
        (declared->width != sensor_w || declared->height != sensor_h))
      return {frame_size_mismatch(path_, frame, declared->width, declared->height, " by its header", sensor_w,
                                  sensor_h),
              true};
    out.image = decode_image_bytes(bytes, &out.bits);
    if (out.image.empty()) return {"cannot decode frame file '" + path_ + "' as an 8/16-bit PNG or TIFF"};
    return {};
  }

 private:
  std::string path_;
};

}  // namespace

std::unique_ptr<FrameContainer> open_image_frames(const std::string& path) {
  return std::make_unique<ImageFrames>(path);
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
