// libFuzzer target: a DLTdv / Argus DLT-11 coefficient file (read_dlt_coefficients_csv) and the
// split of its second camera's coefficients into rangecal's model (camera_from_dlt). The reader opens
// a path, so the input is written to a per-process scratch file.
#include "fuzz_common.hpp"
#include "vision/calibration/dlt_camera_import.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const rangecal::fuzz::ScratchFile file("dlt.csv");
  const std::string& path = file.write(std::string_view(reinterpret_cast<const char*>(data), size));
  rangecal::fuzz::expect_parse_or_error([&] {
    const std::array<double, 11> L = rangecal::read_dlt_coefficients_csv(path, 2);
    rangecal::camera_from_dlt(L, rangecal::SensorGeometry{1280, 800, 0.02, 0.02});
  });
  return 0;
}
