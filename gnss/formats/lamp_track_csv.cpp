#include "gnss/formats/lamp_track_csv.hpp"

#include <Eigen/LU>
#include <array>
#include <limits>
#include <optional>

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "config/physical_ranges.hpp"
#include "gnss/time/csv_utc.hpp"

namespace rangecal {

namespace {

/// The correlation coefficients (ρEN, ρEU, ρNU) of a covariance; nullopt when it is not known
/// (NaN) or a σ is zero (no correlation to state).
std::optional<Eigen::Vector3d> correlations(const Eigen::Matrix3d& cov) {
  if (!cov.allFinite()) return std::nullopt;
  const Eigen::Vector3d sd = cov.diagonal().cwiseMax(0.0).cwiseSqrt();
  if (sd.minCoeff() <= 0) return std::nullopt;
  return Eigen::Vector3d(cov(0, 1) / (sd[0] * sd[1]), cov(0, 2) / (sd[0] * sd[2]),
                         cov(1, 2) / (sd[1] * sd[2]));
}

}  // namespace

std::string format_lamp_track_csv(const LampTrack& track) {
  std::string out = "utc,E,N,U,sdE,sdN,sdU,quality,rEN,rEU,rNU\n";
  out.reserve(out.size() + track.epochs.size() * 120);
  auto it = std::back_inserter(out);
  for (const LampEpoch& e : track.epochs) {
    out += format_iso8601_utc(e.utc, 9);
    fmt::format_to(it, ",{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{}", e.enu[0], e.enu[1], e.enu[2],
                   e.sd_enu[0], e.sd_enu[1], e.sd_enu[2], e.quality);
    if (const auto r = correlations(e.cov_enu)) {
      fmt::format_to(it, ",{:.4f},{:.4f},{:.4f}\n", (*r)[0], (*r)[1], (*r)[2]);
    } else {
      out += ",,,\n";  // not known: the network bundle then takes diag(sd²)
    }
  }
  return out;
}

void write_lamp_track_csv(const std::string& path, const LampTrack& track) {
  write_file_atomic(path, format_lamp_track_csv(track));
}

namespace {

/// The covariance D·R·D from the sd and the correlation columns (all three empty: not known, NaN).
/// Each ρ in [−1, 1]; R must be positive semi-definite (det R ≥ −1e−3 allows the 4-decimal
/// rounding of a nearly singular R).
Eigen::Matrix3d covariance_from_columns(const CsvTable& t, const CsvRecord& r,
                                        const std::array<std::size_t, 3>& cols, const Eigen::Vector3d& sd) {
  const bool empty = t.text(r, cols[0]).empty() && t.text(r, cols[1]).empty() && t.text(r, cols[2]).empty();
  if (empty) return Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  double rho[3];
  for (int k = 0; k < 3; ++k)
    rho[k] = t.number_in(r, cols[static_cast<std::size_t>(k)], -1, 1, "correlation");
  Eigen::Matrix3d R;
  R << 1, rho[0], rho[1], rho[0], 1, rho[2], rho[1], rho[2], 1;
  if (R.determinant() < -1e-3)
    throw_input_error(t.path, r.line, "rEN",
                      "correlations (" + t.text(r, cols[0]) + ", " + t.text(r, cols[1]) + ", " +
                          t.text(r, cols[2]) + ") are not those of any covariance (negative determinant)");
  return sd.asDiagonal() * R * sd.asDiagonal();
}

}  // namespace

LampTrack parse_lamp_track_csv(const std::string& text, const std::string& path) {
  const CsvTable t = parse_csv(text, path);
  const std::size_t cu = t.column("utc"), ce = t.column("E"), cn = t.column("N"), cz = t.column("U"),
                    se = t.column("sdE"), sn = t.column("sdN"), sz = t.column("sdU"),
                    cq = t.column("quality");
  // rEN, rEU, rNU (correlation coefficients) are optional: files written before they existed,
  // or by hand, carry the sd only.
  std::optional<std::array<std::size_t, 3>> rho_cols;
  const auto r_en = t.find_column("rEN"), r_eu = t.find_column("rEU"), r_nu = t.find_column("rNU");
  if (r_en || r_eu || r_nu) rho_cols = {{t.column("rEN"), t.column("rEU"), t.column("rNU")}};
  LampTrack track;
  track.epochs.reserve(t.records.size());
  for (const CsvRecord& r : t.records) {
    LampEpoch e;
    e.utc = csv_utc(t, r, cu);
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
    if (rho_cols) e.cov_enu = covariance_from_columns(t, r, *rho_cols, e.sd_enu);
    track.epochs.push_back(e);
  }
  if (track.epochs.empty()) throw_input_error(path, 1, "utc", "no epochs (only a header)");
  return track;
}

LampTrack read_lamp_track_csv(const std::string& path) {
  return parse_lamp_track_csv(read_file_text(path), path);
}

}  // namespace rangecal
