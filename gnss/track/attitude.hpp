#pragma once
// UAV attitude (SPEC §2, §3.3): roll, pitch, yaw in degrees as flight controllers log them —
// body frame FRD (x forward, y right, z down), navigation frame NED, yaw clockwise from north —
// read from `utc,roll_deg,pitch_deg,yaw_deg` (utc ISO 8601 with `Z`, up to 9 fraction digits),
// interpolated to GNSS epochs, and turned into R_nb = Rz(yaw)·Ry(pitch)·Rx(roll) (seed 002
// eq. 3–4 with the angle names put right: φ is the yaw, θ the pitch, ψ the roll; seeds/NOTES.md).
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

struct Attitude {
  double roll_deg = 0;   ///< right wing down positive, [-180, 180]
  double pitch_deg = 0;  ///< nose up positive, [-90, 90]
  double yaw_deg = 0;    ///< clockwise from north; read in [-360, 360], interpolated in (-180, 180]
};

struct AttitudeSample {
  UtcTime utc;
  Attitude att;
  long line = 0;  ///< 1-based line in the CSV
};

/// Samples strictly increasing in time (≥ 2 to interpolate).
struct AttitudeSeries {
  std::string path;
  std::vector<AttitudeSample> samples;
};

/// Reads the attitude CSV. Throws rangecal::Error (input) naming file, line and column for a
/// missing file or column, a bad time or number, an angle out of range, times not strictly
/// increasing, or fewer than 2 samples.
AttitudeSeries read_attitude_csv(const std::string& path);
/// As read_attitude_csv, from text in memory; `path` is for messages.
AttitudeSeries parse_attitude_csv(const std::string& text, const std::string& path);

/// Wraps an angle in degrees into (-180, 180].
double wrap_deg_180(double a);

/// Attitude at `t` by linear interpolation between the two bracketing samples: roll and pitch
/// linearly, yaw along the shorter arc (crossing ±180° correctly), result yaw in (-180, 180].
/// nullopt when t is outside [first, last] sample time, or when the bracketing samples are more
/// than `max_gap_s` apart (a hole in the attitude log is not bridged).
std::optional<Attitude> interpolate_attitude(const AttitudeSeries& s, UtcTime t, double max_gap_s);

/// R_nb = Rz(yaw)·Ry(pitch)·Rx(roll) (SPEC §2): v_NED = R_nb · v_FRD.
Eigen::Matrix3d rotation_nb(const Attitude& a);

}  // namespace rangecal
