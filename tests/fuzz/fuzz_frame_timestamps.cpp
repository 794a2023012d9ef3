// libFuzzer target: the frame timestamps CSV (parse_frame_timestamps) (tests/fuzz/fuzz_common.hpp;
// docs/reliability.md "Fuzzing").
#include "fuzz_common.hpp"
#include "vision/frames/frame_timestamps_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = rangecal::fuzz::as_string(data, size);
  rangecal::fuzz::expect_parse_or_error(
      [&] { rangecal::parse_frame_timestamps(text, "fuzz/timestamps.csv"); });
  return 0;
}
