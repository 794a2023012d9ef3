#pragma once
// UAV attitude (docs/conventions.md, docs/formats.md): roll, pitch, yaw in degrees as flight controllers log
// them — body frame FRD (x forward, y right, z down), navigation frame NED, yaw clockwise from north — on the
// UTC axis, interpolated to GNSS epochs, and turned into R_nb = Rz(yaw)·Ry(pitch)·Rx(roll) (seed 002 eq. 3–4
// with the angle names put right: φ is the yaw, θ the pitch, ψ the roll; seeds/NOTES.md). The readers are in
// gnss/formats/ (attitude_file.hpp chooses by content: the CSV `utc,roll_deg,pitch_deg,yaw_deg`, a PX4 ULog
// or an ArduPilot DataFlash log).
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
  long line = 0;  ///< 1-based line in the CSV; 0 for samples from a binary log
};

/// Samples strictly increasing in time (≥ 2 to interpolate).
struct AttitudeSeries {
  std::string path;
  std::vector<AttitudeSample> samples;
};

/// Wraps an angle in degrees into (-180, 180].
double wrap_deg_180(double a);

/// Attitude at `t` by linear interpolation between the two bracketing samples: roll and pitch
/// linearly, yaw along the shorter arc (crossing ±180° correctly), result yaw in (-180, 180].
/// nullopt when t is outside [first, last] sample time, or when the bracketing samples are more
/// than `max_gap_s` apart (a hole in the attitude log is not bridged).
std::optional<Attitude> interpolate_attitude(const AttitudeSeries& s, UtcTime t, double max_gap_s);

/// R_nb = Rz(yaw)·Ry(pitch)·Rx(roll) (docs/conventions.md): v_NED = R_nb · v_FRD.
Eigen::Matrix3d rotation_nb(const Attitude& a);

/// Roll, pitch, yaw (degrees, yaw in (-180, 180]) of the unit Hamilton quaternion q = [w, x, y, z]
/// that rotates body FRD vectors into NED (PX4's vehicle_attitude.q), so that rotation_nb of the
/// result is the quaternion's rotation matrix. `q` need not be exactly unit: it is normalised
/// first (a logged float quaternion is unit to ~1e-7); a zero quaternion gives all angles 0.
Attitude attitude_from_quaternion(double w, double x, double y, double z);

}  // namespace rangecal
