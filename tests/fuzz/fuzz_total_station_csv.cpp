// libFuzzer target: the total-station lever-arm CSV (parse_total_station_csv) (tests/fuzz/fuzz_common.hpp;
// docs/reliability.md "Fuzzing").
#include "fuzz_common.hpp"
#include "gnss/track/lever_arm.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = rangecal::fuzz::as_string(data, size);
  rangecal::fuzz::expect_parse_or_error(
      [&] { rangecal::parse_total_station_csv(text, "fuzz/total_station.csv"); });
  return 0;
}
