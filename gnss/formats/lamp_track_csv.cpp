#include "gnss/formats/lamp_track_csv.hpp"

#include <cstdio>

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/physical_ranges.hpp"

namespace rangecal {

std::string format_lamp_track_csv(const LampTrack& track) {
  std::string out = "utc,E,N,U,sdE,sdN,sdU,quality\n";
  out.reserve(out.size() + track.epochs.size() * 96);
  char buf[160];
  for (const LampEpoch& e : track.epochs) {
    out += format_iso8601_utc(e.utc, 9);
    const int n = std::snprintf(buf, sizeof buf, ",%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%d\n", e.enu[0], e.enu[1],
                                e.enu[2], e.sd_enu[0], e.sd_enu[1], e.sd_enu[2], e.quality);
    out.append(buf, static_cast<std::size_t>(n));
  }
  return out;
}

void write_lamp_track_csv(const std::string& path, const LampTrack& track) {
  write_file_atomic(path, format_lamp_track_csv(track));
}

LampTrack parse_lamp_track_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t cu = t.column("utc"), ce = t.column("E"), cn = t.column("N"), cz = t.column("U"),
                    se = t.column("sdE"), sn = t.column("sdN"), sz = t.column("sdU"),
                    cq = t.column("quality");
  LampTrack track;
  track.epochs.reserve(t.records.size());
  for (const CsvRecord& r : t.records) {
    LampEpoch e;
    std::string why;
    const auto utc = parse_iso8601_utc(t.text(r, cu), &why);
    if (!utc) throw_input_error(path, r.line, "utc", "'" + t.text(r, cu) + "': " + why);
    e.utc = *utc;
    if (!track.epochs.empty() && e.utc <= track.epochs.back().utc)
      throw_input_error(path, r.line, "utc",
                        "time is not after the previous line's; epochs must be strictly increasing");
    const auto enu = t.site_enu(r, ce, cn, cz);
    e.enu = {enu[0], enu[1], enu[2]};
    const std::size_t sdcols[3] = {se, sn, sz};
    for (int k = 0; k < 3; ++k)
      e.sd_enu[k] = t.number_in(r, sdcols[k], 0, ranges::kMaxPositionSigmaM, "standard deviation, m");
    const auto q = t.integer(r, cq);
    if (q < 1 || q > 6) throw_input_error(path, r.line, "quality", "'" + t.text(r, cq) + "' is outside 1-6");
    e.quality = static_cast<int>(q);
    track.epochs.push_back(e);
  }
  if (track.epochs.empty()) throw_input_error(path, 1, "utc", "no epochs (only a header)");
  return track;
}

LampTrack read_lamp_track_csv(const std::string& path) {
  return parse_lamp_track_csv(read_file_text(path), path);
}

}  // namespace rangecal
