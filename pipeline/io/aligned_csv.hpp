#pragma once
// `<cam>/aligned.csv`, written by the align stage and read by the detect stage: one row per kept
// frame (pipeline/steps/align_frames.hpp), the lamp at the frame's exact UTC.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <cstdint>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

/// A kept frame: the lamp at the frame's exact UTC. One row of `<cam>/aligned.csv`.
struct AlignedFrame {
  std::int64_t frame = 0;
  UtcTime utc;
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();     ///< interpolated lamp ENU (m)
  Eigen::Vector3d sd_enu = Eigen::Vector3d::Zero();  ///< interpolated 1σ (m)
  double dt_s = 0;                                   ///< frame UTC − nearest epoch UTC (s)
  /// Lamp velocity at the frame's UTC (m/s): the Hermite interpolant's derivative. The bundle's
  /// clock-offset parameter moves the point by −velocity·δ (optim/bundle/bundle_adjustment.hpp).
  Eigen::Vector3d vel_enu = Eigen::Vector3d::Zero();
};

/// `<cam>/aligned.csv`: header `frame,utc,E,N,U,sdE,sdN,sdU,dt_s,vE,vN,vU`; utc ISO 8601 with 9
/// fraction digits; E, N, U and sd in metres with 6 decimals (µm); dt_s with 9 decimals (ns);
/// velocity in m/s with 4 decimals. Deterministic (locale-independent) text.
std::string format_aligned_csv(const std::vector<AlignedFrame>& rows);
/// Writes format_aligned_csv atomically.
void write_aligned_csv(const std::string& path, const std::vector<AlignedFrame>& rows);
/// Reads `<cam>/aligned.csv`. Throws rangecal::Error (input) naming file, line and field for a
/// missing column, an unparsable value, or rows not strictly increasing in frame and utc.
std::vector<AlignedFrame> read_aligned_csv(const std::string& path);
/// As read_aligned_csv, from text in memory; `path` is used for messages only.
std::vector<AlignedFrame> parse_aligned_csv(const std::string& text, const std::string& path);

}  // namespace rangecal
