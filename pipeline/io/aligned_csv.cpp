#include "pipeline/io/aligned_csv.hpp"

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "gnss/time/csv_utc.hpp"

namespace rangecal {

std::string format_aligned_csv(const std::vector<AlignedFrame>& rows) {
  std::string out = "frame,utc,E,N,U,sdE,sdN,sdU,dt_s,vE,vN,vU\n";
  out.reserve(out.size() + rows.size() * 160);
  for (const AlignedFrame& r : rows) {
    fmt::format_to(std::back_inserter(out),
                   "{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.9f},{:.4f},{:.4f},{:.4f}\n",
                   static_cast<long long>(r.frame), format_iso8601_utc(r.utc, 9), r.enu.x(), r.enu.y(),
                   r.enu.z(), r.sd_enu.x(), r.sd_enu.y(), r.sd_enu.z(), r.dt_s, r.vel_enu.x(), r.vel_enu.y(),
                   r.vel_enu.z());
  }
  return out;
}

void write_aligned_csv(const std::string& path, const std::vector<AlignedFrame>& rows) {
  write_file_atomic(path, format_aligned_csv(rows));
}

std::vector<AlignedFrame> parse_aligned_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t c_frame = t.column("frame"), c_utc = t.column("utc");
  const std::size_t c_pos[3] = {t.column("E"), t.column("N"), t.column("U")};
  const std::size_t c_sd[3] = {t.column("sdE"), t.column("sdN"), t.column("sdU")};
  const std::size_t c_dt = t.column("dt_s");
  const std::size_t c_vel[3] = {t.column("vE"), t.column("vN"), t.column("vU")};
  std::vector<AlignedFrame> rows;
  rows.reserve(t.records.size());
  for (const CsvRecord& rec : t.records) {
    AlignedFrame a;
    a.frame = t.integer(rec, c_frame);
    a.utc = csv_utc(t, rec, c_utc);
    for (int k = 0; k < 3; ++k) {
      a.enu[k] = t.number(rec, c_pos[k]);
      a.sd_enu[k] = t.number(rec, c_sd[k]);
      if (a.sd_enu[k] < 0)
        throw_input_error(path, rec.line, t.header[c_sd[k]], "a standard deviation cannot be negative");
    }
    a.dt_s = t.number(rec, c_dt);
    for (int k = 0; k < 3; ++k) a.vel_enu[k] = t.number(rec, c_vel[k]);
    if (!rows.empty() && !(a.frame > rows.back().frame)) {
      throw_input_error(path, rec.line, "frame",
                        "frame " + std::to_string(a.frame) + " does not follow frame " +
                            std::to_string(rows.back().frame) + ": rows must be in frame order");
    }
    if (!rows.empty() && !(a.utc > rows.back().utc)) {
      throw_input_error(path, rec.line, "utc",
                        "time is not after the previous row's: rows must be in time order");
    }
    rows.push_back(a);
  }
  return rows;
}

std::vector<AlignedFrame> read_aligned_csv(const std::string& path) {
  return parse_aligned_csv(read_file_text(path), path);
}

}  // namespace rangecal
