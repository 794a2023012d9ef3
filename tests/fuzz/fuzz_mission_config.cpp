// libFuzzer target: the mission config JSON (parse_mission_config, files not checked)
// (tests/fuzz/fuzz_common.hpp; docs/reliability.md "Fuzzing").
#include "fuzz_common.hpp"
#include "pipeline/mission/mission_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = rangecal::fuzz::as_string(data, size);
  rangecal::fuzz::expect_parse_or_error(
      [&] { rangecal::parse_mission_config(text, "fuzz/mission.json", false); });
  return 0;
}
