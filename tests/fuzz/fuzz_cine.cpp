// libFuzzer target: Phantom .cine files (CineReader). The reader opens a path, so the input is
// written to a per-process scratch file. Only the first and the last image are decoded (with their
// times and exposures), so a run stays fast.
#include "fuzz_common.hpp"
#include "vision/frames/cine_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const rangecal::fuzz::ScratchFile file("rec.cine");
  const std::string& path = file.write(std::string_view(reinterpret_cast<const char*>(data), size));
  rangecal::fuzz::expect_parse_or_error([&] {
    const rangecal::CineReader reader(path);
    const std::size_t n = reader.frame_count();
    for (const std::size_t i : {std::size_t{0}, n - 1}) {
      if (i >= n) continue;
      reader.read_image(i);
      reader.exposure_s(i);
      if (reader.has_times()) {
        reader.frame_time(i);
        reader.frame_irig_locked(i);
      }
    }
  });
  return 0;
}
