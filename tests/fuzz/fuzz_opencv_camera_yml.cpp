// libFuzzer target: an OpenCV camera file (read_opencv_camera_yml: rangecal's reader of OpenCV's
// YAML, config/opencv_yaml.hpp) and its import into rangecal's model (camera_from_opencv). The
// reader opens a path, so the input is written to a per-process scratch file.
#include "fuzz_common.hpp"
#include "vision/camera/opencv_camera_export.hpp"
#include "vision/camera/opencv_camera_import.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const rangecal::fuzz::ScratchFile file("camera.yml");
  const std::string& path = file.write(std::string_view(reinterpret_cast<const char*>(data), size));
  rangecal::fuzz::expect_parse_or_error([&] {
    const rangecal::OpenCvCamera oc = rangecal::read_opencv_camera_yml(path);
    rangecal::camera_from_opencv(oc, 0.005, 0.005);
  });
  return 0;
}
