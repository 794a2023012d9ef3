// libFuzzer target: the pole survey `poles.csv` and the pole picks `poles_px.csv`
// (parse_pole_survey, parse_pole_picks) (tests/fuzz/fuzz_common.hpp; docs/reliability.md "Fuzzing").
#include "fuzz_common.hpp"
#include "gnss/formats/pole_survey_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = rangecal::fuzz::as_string(data, size);
  const rangecal::GeodeticOrigin origin{53.28, -9.06, 50.0};
  rangecal::fuzz::expect_parse_or_error([&] { rangecal::parse_pole_survey(text, "fuzz/poles.csv", origin); });
  // Picks are checked against the image when the sensor is known, against ±1e5 px otherwise.
  rangecal::fuzz::expect_parse_or_error([&] {
    rangecal::parse_pole_picks(text, "fuzz/poles_px.csv", {1280, 800});
  });
  rangecal::fuzz::expect_parse_or_error([&] { rangecal::parse_pole_picks(text, "fuzz/poles_px.csv", {}); });
  return 0;
}
