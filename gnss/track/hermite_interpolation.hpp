#pragma once
// Cubic Hermite interpolation of the lamp track (docs/alignment.md; seed 002 §2.4): the lamp position at
// any UTC instant between two GNSS epochs, never across a gap.
//
// Between epochs k and k+1 (times t0 < t1, h = t1 − t0, s = (t − t0)/h ∈ [0, 1]):
//   p(t) = h00(s)·p0 + h10(s)·h·m0 + h01(s)·p1 + h11(s)·h·m1
//   h00 = 2s³ − 3s² + 1,  h10 = s³ − 2s² + s,  h01 = −2s³ + 3s²,  h11 = s³ − s²
// with tangents m (ENU m/s) at every epoch:
//   - the .pos velocity of the epoch when it carries one (all three components finite);
//   - otherwise the derivative of the parabola through the epoch and its neighbours that are not
//     separated from it by a gap (second-order accurate for uneven spacing): central when both
//     sides are usable, one-sided three-point at a track end or gap edge, two-point when only one
//     neighbour is usable.
// An interval longer than max_gap_s is a gap: instants strictly inside it are not interpolated.
// Instants exactly at an epoch return that epoch, whatever the neighbouring intervals.
//
// The interpolated 1σ is the linear interpolation of the two epochs' sd: PPK errors of epochs a
// fraction of a second apart are strongly correlated (same ambiguities, same multipath), so the
// error of the interpolated point is the weighted mean of theirs, not a root-sum-square.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"
#include "gnss/track/lamp_track.hpp"

namespace rangecal {

enum class TrackSampleStatus {
  ok,            ///< interpolated (or exactly at an epoch)
  before_track,  ///< earlier than the first epoch (no extrapolation)
  after_track,   ///< later than the last epoch (no extrapolation)
  in_gap,        ///< inside an interval longer than max_gap_s
};
const char* to_string(TrackSampleStatus s);

/// The track at one instant. Position, sd and velocity are meaningful only when status is ok.
struct TrackSample {
  TrackSampleStatus status = TrackSampleStatus::ok;
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();      ///< lamp ENU (m)
  Eigen::Vector3d sd_enu = Eigen::Vector3d::Zero();   ///< 1σ of E, N, U (m)
  Eigen::Vector3d vel_enu = Eigen::Vector3d::Zero();  ///< derivative of the interpolant (m/s)
  /// Index of the epoch that starts the bracketing interval (for in_gap: the epoch before the gap).
  std::size_t segment = 0;
  /// Length of the bracketing interval (s); for in_gap, the gap's length. 0 when exactly at an epoch.
  double interval_s = 0;
};

/// A lamp track prepared for interpolation: epoch times, positions, sd and tangents.
class HermiteTrack {
 public:
  /// Validates and prepares `track`. max_gap_s > 0 (s). `source` names the track in messages
  /// (e.g. the lamp_track.csv path). Throws rangecal::Error (input) when the track is empty or its
  /// epochs are not strictly increasing in time, or a position/sd is not finite; (usage) when
  /// max_gap_s is not a positive number.
  HermiteTrack(const LampTrack& track, double max_gap_s, const std::string& source = "lamp track");

  /// The lamp at instant t (see the header comment for the method). O(log n).
  TrackSample sample(UtcTime t) const;

  std::size_t size() const { return t_ns_.size(); }
  UtcTime epoch_time(std::size_t i) const { return UtcTime{t_ns_[i]}; }
  /// Tangent used at epoch i (ENU m/s) and whether it came from the .pos velocity.
  const Eigen::Vector3d& tangent(std::size_t i) const { return m_[i]; }
  bool tangent_from_velocity(std::size_t i) const { return from_velocity_[i] != 0; }
  double max_gap_s() const { return max_gap_s_; }

 private:
  std::vector<std::int64_t> t_ns_;
  std::vector<Eigen::Vector3d> p_, sd_, m_;
  std::vector<char> from_velocity_;
  std::int64_t max_gap_ns_ = 0;
  double max_gap_s_ = 0;
};

}  // namespace rangecal
