#include "vision/frames/frame_container.hpp"

#include <stdexcept>

namespace rangecal {

std::vector<UtcTime> FrameContainer::own_times(std::optional<double>) const {
  // The registry only asks formats that declare a time source of their own: reaching here is a
  // registry entry that promises times its container does not give.
  throw std::logic_error("this frame format carries no time stamps of its own");
}

std::string frame_size_mismatch(const std::string& file, std::int64_t frame, int w, int h,
                                const std::string& how, int sensor_w, int sensor_h) {
  return "frame '" + file + "' (frame " + std::to_string(frame) + ") is " + std::to_string(w) + "x" +
         std::to_string(h) + " px" + how + "; the sensor is " + std::to_string(sensor_w) + "x" +
         std::to_string(sensor_h);
}

std::string frame_beyond_end(const std::string& file, std::int64_t frame) {
  return "frame " + std::to_string(frame) + " is beyond the end of '" + file + "'";
}

}  // namespace rangecal
