#include "pipeline/io/target_path_csv.hpp"

#include "config/csv_table.hpp"
#include "config/error.hpp"

namespace rangecal {

std::vector<TargetPathPoint> parse_target_path_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t ct = t.column("t_s"), ce = t.column("E"), cn = t.column("N"), cu = t.column("U");
  std::vector<TargetPathPoint> out;
  for (const CsvRecord& r : t.records) {
    TargetPathPoint p;
    p.line = r.line;
    // A week at most: a path is a test's minutes, and a longer one is a unit slip (ms for s).
    p.t_s = t.number_in(r, ct, 0, 7 * 86400.0, "time since the path's start, s");
    const std::array<double, 3> enu = t.site_enu(r, ce, cn, cu);
    p.enu_m = Eigen::Vector3d(enu[0], enu[1], enu[2]);
    if (!out.empty() && !(p.t_s > out.back().t_s))
      throw_input_error(path, r.line, "t_s",
                        "the time does not follow the previous row's (it must increase)");
    out.push_back(p);
  }
  if (out.size() < 2)
    throw_input_error(
        path, t.header_line, "t_s",
        "a target path needs at least two rows (waypoints), found " + std::to_string(out.size()));
  return out;
}

std::vector<TargetPathPoint> read_target_path_csv(const std::string& path) {
  return parse_target_path_csv(read_file_text(path), path);
}

}  // namespace rangecal
