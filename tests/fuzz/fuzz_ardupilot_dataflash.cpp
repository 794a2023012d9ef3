// libFuzzer target: ArduPilot DataFlash logs (walk_dataflash with every column read, then
// dataflash_attitude) (tests/fuzz/fuzz_common.hpp; docs/reliability.md "Fuzzing").
#include "fuzz_common.hpp"
#include "gnss/formats/ardupilot_dataflash.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  rangecal::fuzz::expect_parse_or_error([&] {
    rangecal::walk_dataflash(bytes, "fuzz/log.bin",
                             [](const rangecal::DataflashFormat& f, std::string_view message) {
                               for (std::size_t c = 0; c < f.columns.size(); ++c) {
                                 rangecal::dataflash_number(f, c, message);
                                 rangecal::dataflash_integer(f, c, message);
                               }
                             });
  });
  rangecal::fuzz::expect_parse_or_error([&] {
    rangecal::AutopilotAttitudeReport report;
    rangecal::dataflash_attitude(bytes, "fuzz/log.bin", &report);
  });
  return 0;
}
