// libFuzzer target: the correspondences CSV (parse_correspondences_csv) (tests/fuzz/fuzz_common.hpp;
// docs/reliability.md "Fuzzing").
#include "fuzz_common.hpp"
#include "pipeline/io/correspondences_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = rangecal::fuzz::as_string(data, size);
  rangecal::fuzz::expect_parse_or_error(
      [&] { rangecal::parse_correspondences_csv(text, "fuzz/correspondences.csv"); });
  return 0;
}
