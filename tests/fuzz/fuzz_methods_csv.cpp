// libFuzzer target: the methods CSV (parse_methods_csv) (tests/fuzz/fuzz_common.hpp; docs/reliability.md
// "Fuzzing").
#include "fuzz_common.hpp"
#include "pipeline/io/methods_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = rangecal::fuzz::as_string(data, size);
  rangecal::fuzz::expect_parse_or_error([&] { rangecal::parse_methods_csv(text, "fuzz/methods.csv"); });
  return 0;
}
