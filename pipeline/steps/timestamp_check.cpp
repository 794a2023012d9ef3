#include "pipeline/steps/timestamp_check.hpp"

#include <cmath>
#include <optional>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "vision/calibration/dlt.hpp"

namespace rangecal {
namespace {

constexpr int kMinPoints = 12;

// rms (px) of one linear DLT fitted to the pairs with the track sampled at stamp + δ; nullopt
// when too few pairs fall on the track or the DLT is degenerate.
std::optional<double> dlt_rms_at(const std::vector<std::pair<UtcTime, Eigen::Vector2d>>& pixels,
                                 const HermiteTrack& track, double offset_s, int* n_used) {
  std::vector<PointCorrespondence> pts;
  const auto shift_ns = static_cast<std::int64_t>(std::llround(offset_s * 1e9));
  for (const auto& [t, uv] : pixels) {
    const TrackSample s = track.sample(UtcTime{t.ns + shift_ns});
    if (s.status == TrackSampleStatus::ok) pts.push_back({s.enu, uv});
  }
  if (n_used) *n_used = static_cast<int>(pts.size());
  if (static_cast<int>(pts.size()) < kMinPoints) return std::nullopt;
  try {
    const ProjectionMatrix P = dlt_projection_matrix(pts);
    double sum = 0;
    for (const auto& p : pts) {
      const Eigen::Vector3d x = P * p.world.homogeneous();
      if (!(std::abs(x.z()) > 0)) return std::nullopt;
      sum += (x.hnormalized() - p.pixel).squaredNorm();
    }
    const double rms = std::sqrt(sum / static_cast<double>(pts.size()));
    return std::isfinite(rms) ? std::optional<double>(rms) : std::nullopt;
  } catch (const Error&) {
    return std::nullopt;
  }
}

}  // namespace

const std::vector<double>& default_timestamp_offsets_s() {
  static const std::vector<double> c = {-19, -18, -17, -2, -1, 1, 2, 17, 18, 19};
  return c;
}

TimestampOffsetCheck check_timestamp_offset(const std::vector<std::pair<UtcTime, Eigen::Vector2d>>& pixels,
                                            const HermiteTrack& track,
                                            const std::vector<double>& candidates_s) {
  TimestampOffsetCheck r;
  const std::optional<double> zero = dlt_rms_at(pixels, track, 0.0, &r.n_points);
  if (!zero) return r;
  r.rms_at_zero_px = r.rms_at_best_px = *zero;
  for (const double d : candidates_s) {
    int n = 0;
    const std::optional<double> rms = dlt_rms_at(pixels, track, d, &n);
    // A candidate must explain at least half as many pairs as the stamps do to compete.
    if (rms && 2 * n >= r.n_points && *rms < r.rms_at_best_px) {
      r.rms_at_best_px = *rms;
      r.best_offset_s = d;
    }
  }
  // The DLT has no distortion term, so even right pairs leave a few px with a long lens' k1 and
  // a flexible 11-parameter fit absorbs part of a wrong pairing when the pairs are few (a leap
  // second leaves only the part of the flight that still overlaps the track): a 1.5× and 2 px
  // better fit is taken as decisive. Right stamps are never beaten: shifted by any candidate,
  // the flight's motion (hovers, transits) breaks the pinhole fit by tens of px or more.
  r.offset_detected = r.best_offset_s != 0 && r.rms_at_best_px * 1.5 < r.rms_at_zero_px &&
                      r.rms_at_zero_px - r.rms_at_best_px > 2.0;
  return r;
}

std::string describe_timestamp_offset(const TimestampOffsetCheck& tc) {
  return fmt::format(
      "frame time stamps look off by {:+.0f} s: the lamp pairs fit one pinhole camera with rms "
      "{:.2f} px when the track is taken {:+.0f} s from each stamp, against {:.1f} px as stamped — a "
      "{}; correct the time stamps (the calibration of this camera will be wrong)",
      -tc.best_offset_s, tc.rms_at_best_px, tc.best_offset_s, tc.rms_at_zero_px,
      std::abs(std::abs(tc.best_offset_s) - 18) <= 1 ? "GPST/UTC leap-second mix-up"
                                                     : "whole-second clock error");
}

}  // namespace rangecal
