// libFuzzer target: the lamp track CSV (parse_lamp_track_csv) (tests/fuzz/fuzz_common.hpp;
// docs/reliability.md "Fuzzing").
#include "fuzz_common.hpp"
#include "gnss/formats/lamp_track_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = rangecal::fuzz::as_string(data, size);
  rangecal::fuzz::expect_parse_or_error([&] { rangecal::parse_lamp_track_csv(text, "fuzz/lamp_track.csv"); });
  return 0;
}
