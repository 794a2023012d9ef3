// libFuzzer target: network.json, every reader the intersect stage and the report use (the joint
// covariance's cross blocks, the datum floor, the float epochs, the statistics object) on a scratch
// file (tests/fuzz/fuzz_common.hpp; docs/reliability.md "Fuzzing").
#include <nlohmann/json.hpp>

#include "fuzz_common.hpp"
#include "pipeline/io/network_json.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const rangecal::fuzz::ScratchFile file("network.json");
  const std::string& path = file.write(std::string_view(reinterpret_cast<const char*>(data), size));
  const std::vector<std::string> ids{"cam1", "cam2"};
  const std::vector<std::vector<rangecal::CameraParameter>> params{
      {rangecal::CameraParameter::f, rangecal::CameraParameter::k1},
      {rangecal::CameraParameter::f, rangecal::CameraParameter::k1}};
  rangecal::fuzz::expect_parse_or_error([&] { rangecal::read_network_cross_covariances(path, ids); });
  rangecal::fuzz::expect_parse_or_error(
      [&] { rangecal::read_network_cross_covariances(path, ids, &params); });
  rangecal::fuzz::expect_parse_or_error([&] { rangecal::read_network_datum_floor(path, ids, &params); });
  rangecal::fuzz::expect_parse_or_error([&] { rangecal::read_network_float_epochs(path); });
  rangecal::fuzz::expect_parse_or_error([&] {
    const nlohmann::json j = nlohmann::json::parse(rangecal::fuzz::as_string(data, size), nullptr, false);
    if (j.is_object() && j.contains("statistics"))
      rangecal::parse_network_statistics_json(j["statistics"], path, "statistics");
  });
  return 0;
}
