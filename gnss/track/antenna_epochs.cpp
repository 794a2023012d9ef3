#include "gnss/track/antenna_epochs.hpp"

#include <algorithm>
#include <cmath>

#include "config/error.hpp"
#include "config/physical_ranges.hpp"

namespace rangecal {

std::vector<AntennaEpoch> merge_antenna_epochs(const std::vector<PosFile>& files, const LocalEnu& site) {
  std::size_t n = 0;
  for (const PosFile& f : files) n += f.epochs.size();
  std::vector<AntennaEpoch> out;
  out.reserve(n);
  for (std::size_t fi = 0; fi < files.size(); ++fi) {
    const PosFile& f = files[fi];
    for (const PosEpoch& e : f.epochs) {
      const EnuFix fix = to_site_enu(f, e, site);
      // A fix on the Earth but far from the site is a wrong origin in the config, or a file from
      // another mission: refuse it rather than produce a track kilometres away.
      if (!ranges::within_site_box(fix.enu.x(), fix.enu.y(), fix.enu.z()))
        throw_input_error(f.path, e.line, "position",
                          "the antenna is " +
                              std::to_string(static_cast<long long>(fix.enu.head<2>().norm() / 1000)) +
                              " km from the site origin horizontally and " +
                              std::to_string(static_cast<long long>(fix.enu.z())) +
                              " m above it, outside the site box (±50 km, ±21 km): is the site origin in the "
                              "mission config right, and is this the mission's file?");
      AntennaEpoch a;
      a.utc = e.utc;
      a.enu = fix.enu;
      a.cov_enu = fix.cov_enu;
      a.sd_local = fix.sd_local;
      a.vel_enu = fix.vel_enu;
      a.quality = e.quality;
      a.ns = e.ns;
      a.file_index = static_cast<int>(fi);
      a.line = e.line;
      out.push_back(a);
    }
  }
  // Each file is already strictly increasing; a stable sort keeps that and merges the files.
  if (files.size() > 1) {
    std::stable_sort(out.begin(), out.end(),
                     [](const AntennaEpoch& a, const AntennaEpoch& b) { return a.utc < b.utc; });
    for (std::size_t i = 1; i < out.size(); ++i) {
      if (out[i].utc == out[i - 1].utc) {
        const AntennaEpoch& a = out[i - 1];
        const AntennaEpoch& b = out[i];
        throw_input_error(files[b.file_index].path, b.line, "time",
                          "epoch " + format_iso8601_utc(b.utc) + " also appears in " +
                              files[a.file_index].path + " line " + std::to_string(a.line) +
                              "; overlapping .pos files are not merged");
      }
    }
  }
  return out;
}

}  // namespace rangecal
