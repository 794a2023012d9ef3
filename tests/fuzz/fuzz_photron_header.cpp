// libFuzzer target: Photron .cihx / .cih headers (parse_photron_header in both forms, then the
// header clock) (tests/fuzz/fuzz_common.hpp; docs/reliability.md "Fuzzing").
#include "fuzz_common.hpp"
#include "vision/frames/photron_cih.hpp"

namespace {
void parse_as(const std::string& bytes, rangecal::PhotronHeaderFormat format) {
  rangecal::fuzz::expect_parse_or_error([&] {
    const rangecal::PhotronHeader h = rangecal::parse_photron_header(bytes, "fuzz/rec.cihx", format);
    h.frame_bytes();
    const rangecal::PhotronFrameClock clock = rangecal::photron_frame_clock(h, 2.0);
    clock.frame_time(0);
    clock.frame_time(h.total_frame - 1);
  });
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes = rangecal::fuzz::as_string(data, size);
  parse_as(bytes, rangecal::PhotronHeaderFormat::cihx);
  parse_as(bytes, rangecal::PhotronHeaderFormat::cih);
  return 0;
}
