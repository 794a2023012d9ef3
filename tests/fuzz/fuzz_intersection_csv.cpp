// libFuzzer target: the intersection CSV (parse_intersection_csv) (tests/fuzz/fuzz_common.hpp;
// docs/reliability.md "Fuzzing").
#include "fuzz_common.hpp"
#include "pipeline/io/intersection_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = rangecal::fuzz::as_string(data, size);
  rangecal::fuzz::expect_parse_or_error(
      [&] { rangecal::parse_intersection_csv(text, "fuzz/intersection.csv"); });
  return 0;
}
