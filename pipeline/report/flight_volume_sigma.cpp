#include "pipeline/report/flight_volume_sigma.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rangecal {
namespace {

struct SliceGrid {
  Eigen::Vector2d e_range_m, n_range_m;
  double up_m = 0;
};

std::optional<SliceGrid> flight_grid(const ReportData& d) {
  std::vector<Eigen::Vector3d> pts;
  if (d.lamp_track)
    for (const LampEpoch& e : d.lamp_track->epochs) pts.push_back(e.enu);
  for (const SurveyedPole& p : d.survey) pts.push_back(p.enu);
  if (d.intersection)
    for (const IntersectionRow& r : *d.intersection) pts.push_back(r.survey_enu);
  if (pts.empty()) return std::nullopt;
  Eigen::Vector3d lo = pts[0], hi = pts[0];
  for (const Eigen::Vector3d& p : pts) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Eigen::Vector3d pad = ((hi - lo) * 0.1).cwiseMax(1.0);
  SliceGrid g;
  g.e_range_m = Eigen::Vector2d(lo.x() - pad.x(), hi.x() + pad.x());
  g.n_range_m = Eigen::Vector2d(lo.y() - pad.y(), hi.y() + pad.y());
  if (d.intersection && !d.intersection->empty()) {
    for (const IntersectionRow& r : *d.intersection) g.up_m += r.survey_enu.z();
    g.up_m /= static_cast<double>(d.intersection->size());
  } else {
    std::vector<double> u;
    for (const Eigen::Vector3d& p : pts) u.push_back(p.z());
    std::nth_element(u.begin(), u.begin() + static_cast<std::ptrdiff_t>(u.size() / 2), u.end());
    g.up_m = u[u.size() / 2];
  }
  return g;
}

IntersectionSigmaSlice slice_on(const SliceGrid& g, const std::vector<const CalibrationResult*>& cams,
                                double pick_sigma_px, const CrossCovariances* cross) {
  return intersection_sigma_slice(cams, g.e_range_m, g.n_range_m, g.up_m, 36, 28, pick_sigma_px, cross);
}

}  // namespace

SliceStats slice_stats(const IntersectionSigmaSlice& slice) {
  std::vector<double> v;
  for (Eigen::Index k = 0; k < slice.sigma_m.size(); ++k)
    if (std::isfinite(slice.sigma_m(k))) v.push_back(slice.sigma_m(k));
  SliceStats st;
  st.n = static_cast<int>(v.size());
  if (v.empty()) return st;
  std::sort(v.begin(), v.end());
  st.min = v.front();
  st.median = v[v.size() / 2];
  st.max = v.back();
  return st;
}

FlightVolumeSigma flight_volume_sigma(const ReportData& d) {
  FlightVolumeSigma out;
  const std::vector<const CalibrationResult*> cams = calibrated_cameras(d);
  const std::optional<SliceGrid> g = flight_grid(d);
  if (cams.size() < 2 || !g) return out;
  out.slice = slice_on(*g, cams, d.pick_sigma_px, network_cross_or_null(d));
  out.stats = slice_stats(*out.slice);
  if (!d.network_datum_floor || d.network_datum_floor->blocks.size() != cams.size()) return out;
  // The floor's own blocks in place of each calibration's covariance and the cross blocks
  // (predict_intersection takes a camera's own block from its calibration).
  const CrossCovariances& blocks = d.network_datum_floor->blocks;
  std::vector<CalibrationResult> floor;
  for (std::size_t a = 0; a < cams.size(); ++a) {
    floor.push_back(*cams[a]);
    floor.back().covariance = blocks[a][a];
  }
  std::vector<const CalibrationResult*> floor_cams;
  for (const CalibrationResult& c : floor) floor_cams.push_back(&c);
  out.datum_floor = slice_on(*g, floor_cams, d.pick_sigma_px, &blocks);
  out.datum_floor_image_factor = d.network_datum_floor->image_factor;
  // Both medians over the cells where both have a σ, so that the ratio compares like with like.
  IntersectionSigmaSlice both = *out.slice, floor_both = *out.datum_floor;
  for (Eigen::Index k = 0; k < both.sigma_m.size(); ++k)
    if (!std::isfinite(both.sigma_m(k)) || !std::isfinite(floor_both.sigma_m(k)))
      both.sigma_m(k) = floor_both.sigma_m(k) = std::numeric_limits<double>::quiet_NaN();
  out.datum_floor_stats = slice_stats(floor_both);
  const SliceStats st = slice_stats(both);
  if (st.n > 0 && out.datum_floor_stats.median > 0)
    out.over_datum_floor = st.median / out.datum_floor_stats.median;
  return out;
}

}  // namespace rangecal
