// libFuzzer target: the simulation scenario JSON (parse_scenario) (tests/fuzz/fuzz_common.hpp;
// docs/reliability.md "Fuzzing").
#include "fuzz_common.hpp"
#include "pipeline/simulate/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = rangecal::fuzz::as_string(data, size);
  rangecal::fuzz::expect_parse_or_error([&] { rangecal::parse_scenario(text, "fuzz/scenario.json"); });
  return 0;
}
