#include "gnss/formats/autopilot_attitude_series.hpp"

#include "config/error.hpp"

namespace rangecal {

AttitudeSeries autopilot_attitude_series(const std::vector<BootAttitudeSample>& samples,
                                         const std::string& path, const AutopilotAttitudeNames& names,
                                         AutopilotAttitudeReport rep, AutopilotAttitudeReport* report) {
  AttitudeSeries s;
  s.path = path;
  s.samples.reserve(samples.size());
  std::int64_t last = 0;
  for (const BootAttitudeSample& r : samples) {
    if (!s.samples.empty() && r.boot_us <= last) {
      ++rep.attitude_not_increasing;
      continue;
    }
    last = r.boot_us;
    AttitudeSample a;
    a.utc = rep.fit.to_utc(r.boot_us);
    a.att = r.att;
    s.samples.push_back(a);
  }
  rep.attitude_samples = s.samples.size();
  if (s.samples.size() < 2)
    throw_input_error(path, 0, names.field,
                      std::to_string(s.samples.size()) + " usable attitude samples of " +
                          std::to_string(rep.attitude_messages) + " " + names.messages + " (" +
                          std::to_string(rep.attitude_invalid) + " " + names.invalid + ", " +
                          std::to_string(rep.attitude_not_increasing) +
                          " not after the previous); at least 2 are needed to interpolate");
  rep.utc_start = s.samples.front().utc;
  rep.utc_end = s.samples.back().utc;
  if (report) *report = rep;
  return s;
}

}  // namespace rangecal
