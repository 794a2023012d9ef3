// libFuzzer target: RTKLIB .pos solutions (parse_rtklib_pos) (tests/fuzz/fuzz_common.hpp;
// docs/reliability.md "Fuzzing").
#include "fuzz_common.hpp"
#include "gnss/formats/rtklib_pos_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  rangecal::fuzz::expect_parse_or_error([&] { rangecal::parse_rtklib_pos(text, "fuzz/rover.pos"); });
  return 0;
}
