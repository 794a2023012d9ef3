#include "pipeline/io/lamp_track_adjusted_csv.hpp"

#include <cmath>
#include <map>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/time/csv_utc.hpp"

namespace rangecal {

std::string format_lamp_track_adjusted_csv(const LampTrack& track, const NetworkResult& r,
                                           const std::vector<long>& epoch_of_point) {
  std::map<long, std::size_t> rows;  // epoch → point, in time order
  for (std::size_t k = 0; k < epoch_of_point.size() && k < r.points.size(); ++k)
    if (epoch_of_point[k] >= 0 && r.points[k].used) rows[epoch_of_point[k]] = k;
  std::string out = "utc,E,N,U,sdE,sdN,sdU,dE,dN,dU,flag\n";
  for (const auto& [e, k] : rows) {
    const NetworkPointResult& p = r.points[k];
    const Eigen::Vector3d sd = p.cov.diagonal().cwiseMax(0.0).cwiseSqrt();
    fmt::format_to(
        std::back_inserter(out), "{},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{}\n",
        format_iso8601_utc(track.epochs[static_cast<std::size_t>(e)].utc), p.enu.x(), p.enu.y(), p.enu.z(),
        sd.x(), sd.y(), sd.z(), p.correction.x(), p.correction.y(), p.correction.z(), p.ppk_outlier ? 1 : 0);
  }
  return out;
}

std::vector<LampTrackAdjustedRow> parse_lamp_track_adjusted_csv(const std::string& text,
                                                                const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t c_utc = t.column("utc"), c_flag = t.column("flag");
  const char* names[9] = {"E", "N", "U", "sdE", "sdN", "sdU", "dE", "dN", "dU"};
  std::size_t c[9];
  for (int k = 0; k < 9; ++k) c[k] = t.column(names[k]);
  std::vector<LampTrackAdjustedRow> rows;
  rows.reserve(t.records.size());
  for (const CsvRecord& rec : t.records) {
    LampTrackAdjustedRow r;
    r.line = rec.line;
    r.utc = csv_utc(t, rec, c_utc);
    // One row per epoch in time order (the writer's map): a repeated or earlier time is a damaged file.
    if (!rows.empty() && !(rows.back().utc < r.utc))
      throw_input_error(path, rec.line, "utc",
                        "not after the previous row's " + format_iso8601_utc(rows.back().utc));
    for (int k = 0; k < 3; ++k) {
      r.enu[k] = t.number(rec, c[k]);
      r.sd_enu[k] = t.number(rec, c[3 + k]);
      if (r.sd_enu[k] < 0) throw_input_error(path, rec.line, names[3 + k], "negative standard deviation");
      r.correction[k] = t.number(rec, c[6 + k]);
    }
    const std::string& flag = t.text(rec, c_flag);
    if (flag != "0" && flag != "1") throw_input_error(path, rec.line, "flag", "'" + flag + "' is not 0 or 1");
    r.flagged = flag == "1";
    rows.push_back(r);
  }
  return rows;
}

std::vector<LampTrackAdjustedRow> read_lamp_track_adjusted_csv(const std::string& path) {
  return parse_lamp_track_adjusted_csv(read_file_text(path), path);
}

}  // namespace rangecal
