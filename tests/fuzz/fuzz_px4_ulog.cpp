// libFuzzer target: PX4 ULog logs (parse_ulog) and their attitude on the UTC axis (ulog_attitude)
// (tests/fuzz/fuzz_common.hpp; docs/reliability.md "Fuzzing").
#include "fuzz_common.hpp"
#include "gnss/formats/px4_ulog.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  rangecal::fuzz::expect_parse_or_error([&] {
    const rangecal::UlogLog log = rangecal::parse_ulog(rangecal::fuzz::as_string(data, size), "fuzz/log.ulg");
    // Every numeric field of the first D messages, as an `inspect` would touch them (a bounded
    // number, so that a run stays fast on real logs).
    for (std::size_t i = 0; i < log.data.size() && i < 32; ++i) {
      const rangecal::UlogDataMessage& m = log.data[i];
      const std::size_t format = log.subscriptions.at(m.subscription).format;
      for (const rangecal::UlogField& f : log.formats.at(format).fields)
        if (const auto ref = rangecal::find_ulog_field(log, format, f.name);
            ref && ref->type != rangecal::UlogType::nested && ref->type != rangecal::UlogType::character)
          rangecal::ulog_number(log, m, *ref, 0);
    }
    rangecal::AutopilotAttitudeReport report;
    rangecal::ulog_attitude(log, &report);
  });
  return 0;
}
