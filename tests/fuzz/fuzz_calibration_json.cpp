// libFuzzer target: calibration.json (calibration_from_json_text) (tests/fuzz/fuzz_common.hpp;
// docs/reliability.md "Fuzzing").
#include "fuzz_common.hpp"
#include "pipeline/io/calibration_json.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = rangecal::fuzz::as_string(data, size);
  rangecal::fuzz::expect_parse_or_error(
      [&] { rangecal::calibration_from_json_text(text, "fuzz/calibration.json"); });
  return 0;
}
