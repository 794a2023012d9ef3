#include "pipeline/io/correspondences_csv.hpp"

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "config/physical_ranges.hpp"
#include "gnss/time/csv_utc.hpp"

namespace rangecal {

std::string format_correspondences_csv(const std::vector<Correspondence>& pairs) {
  bool with_sd = !pairs.empty(), with_vel = !pairs.empty(), with_sigma = false;
  for (const auto& p : pairs) {
    with_sd = with_sd && p.sd_enu.has_value(), with_vel = with_vel && p.vel_enu;
    with_sigma = with_sigma || p.pixel_sigma_px;
  }
  std::string out = "utc,E,N,U,u,v,residual_px,used";
  out += with_sd ? ",sdE,sdN,sdU" : "";
  out += with_vel ? ",vE,vN,vU" : "";
  out += with_sigma ? ",pixel_sigma_px\n" : "\n";
  auto it = std::back_inserter(out);
  for (const auto& p : pairs) {
    out += format_iso8601_utc(p.utc, 9);
    fmt::format_to(it, ",{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},", p.enu.x(), p.enu.y(), p.enu.z(), p.uv.x(),
                   p.uv.y());
    if (p.residual_px) fmt::format_to(it, "{:.4f}", *p.residual_px);
    out += ",";
    if (p.used) out += *p.used ? "1" : "0";
    if (with_sd) {
      fmt::format_to(it, ",{:.4f},{:.4f},{:.4f}", p.sd_enu->x(), p.sd_enu->y(), p.sd_enu->z());
    }
    if (with_vel) {
      fmt::format_to(it, ",{:.4f},{:.4f},{:.4f}", p.vel_enu->x(), p.vel_enu->y(), p.vel_enu->z());
    }
    if (with_sigma) {
      out += ",";
      if (p.pixel_sigma_px) fmt::format_to(it, "{:.4f}", *p.pixel_sigma_px);
    }
    out += "\n";
  }
  return out;
}

void write_correspondences_csv(const std::string& path, const std::vector<Correspondence>& pairs) {
  write_file_atomic(path, format_correspondences_csv(pairs));
}

std::vector<Correspondence> read_correspondences_csv(const std::string& path) {
  return parse_correspondences_csv(read_file_text(path), path);
}

std::vector<Correspondence> parse_correspondences_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t c_utc = t.column("utc"), c_e = t.column("E"), c_n = t.column("N"), c_u = t.column("U"),
                    c_pu = t.column("u"), c_pv = t.column("v");
  const auto c_res = t.find_column("residual_px");
  const auto c_used = t.find_column("used");
  const auto c_se = t.find_column("sdE"), c_sn = t.find_column("sdN"), c_su = t.find_column("sdU");
  if ((c_se || c_sn || c_su) && !(c_se && c_sn && c_su))
    throw_input_error(path, 1, "sdE", "the world-sd columns come as a set: sdE,sdN,sdU");
  const auto c_ve = t.find_column("vE"), c_vn = t.find_column("vN"), c_vu = t.find_column("vU");
  if ((c_ve || c_vn || c_vu) && !(c_ve && c_vn && c_vu))
    throw_input_error(path, 1, "vE", "the velocity columns come as a set: vE,vN,vU");
  const auto c_sigma = t.find_column("pixel_sigma_px");
  std::vector<Correspondence> out;
  out.reserve(t.records.size());
  for (const auto& r : t.records) {
    Correspondence p;
    const UtcTime utc = csv_utc(t, r, c_utc);
    if (!out.empty() && !(out.back().utc < utc))
      throw_input_error(path, r.line, "utc",
                        "time does not increase (previous line has the same or a later time)");
    p.utc = utc;
    p.line = r.line;
    const double px = ranges::kMaxPixelCoordinatePx;
    const auto enu = t.site_enu(r, c_e, c_n, c_u);
    p.enu = {enu[0], enu[1], enu[2]};
    p.uv = {t.number_in(r, c_pu, -px, px, "pixel"), t.number_in(r, c_pv, -px, px, "pixel")};
    if (c_res && !t.text(r, *c_res).empty()) p.residual_px = t.number(r, *c_res);
    if (c_used && !t.text(r, *c_used).empty()) {
      const std::string& s = t.text(r, *c_used);
      if (s != "0" && s != "1") throw_input_error(path, r.line, "used", "'" + s + "' is not 0, 1 or blank");
      p.used = s == "1";
    }
    if (c_se) {
      const double s = ranges::kMaxPositionSigmaM;
      p.sd_enu = Eigen::Vector3d(t.number_in(r, *c_se, 0, s, "standard deviation, m"),
                                 t.number_in(r, *c_sn, 0, s, "standard deviation, m"),
                                 t.number_in(r, *c_su, 0, s, "standard deviation, m"));
    }
    if (c_ve) {
      const double v = ranges::kMaxSpeedMps;
      p.vel_enu = Eigen::Vector3d(t.number_in(r, *c_ve, -v, v, "velocity, m/s"),
                                  t.number_in(r, *c_vn, -v, v, "velocity, m/s"),
                                  t.number_in(r, *c_vu, -v, v, "velocity, m/s"));
    }
    if (c_sigma && !t.text(r, *c_sigma).empty())
      p.pixel_sigma_px = t.number_in(r, *c_sigma, 1e-6, 100, "the pixel's 1σ per axis, px, > 0 and ≤ 100");
    out.push_back(p);
  }
  return out;
}

}  // namespace rangecal
