#include "gnss/track/attitude.hpp"

#include <algorithm>
#include <cmath>

namespace rangecal {
namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
}

double wrap_deg_180(double a) {
  double r = std::fmod(a, 360.0);
  if (r <= -180.0) r += 360.0;
  if (r > 180.0) r -= 360.0;
  return r;
}

std::optional<Attitude> interpolate_attitude(const AttitudeSeries& s, UtcTime t, double max_gap_s) {
  const auto& v = s.samples;
  if (v.empty() || t < v.front().utc || t > v.back().utc) return std::nullopt;
  auto it =
      std::upper_bound(v.begin(), v.end(), t, [](UtcTime x, const AttitudeSample& a) { return x < a.utc; });
  if (it == v.end()) {  // t is exactly the last sample
    Attitude a = v.back().att;
    a.yaw_deg = wrap_deg_180(a.yaw_deg);
    return a;
  }
  const AttitudeSample& b = *it;
  const AttitudeSample& a = *(it - 1);
  const std::int64_t span = b.utc.ns - a.utc.ns;
  if (static_cast<double>(span) * 1e-9 > max_gap_s) return std::nullopt;
  // Fraction from integer ns: exact enough (span < 2^53 ns).
  const double f = static_cast<double>(t.ns - a.utc.ns) / static_cast<double>(span);
  Attitude r;
  r.roll_deg = a.att.roll_deg + f * (b.att.roll_deg - a.att.roll_deg);
  r.pitch_deg = a.att.pitch_deg + f * (b.att.pitch_deg - a.att.pitch_deg);
  // Yaw along the shorter arc: 179° → −179° passes through 180°, not through 0°.
  const double dyaw = wrap_deg_180(b.att.yaw_deg - a.att.yaw_deg);
  r.yaw_deg = wrap_deg_180(a.att.yaw_deg + f * dyaw);
  return r;
}

Eigen::Matrix3d rotation_nb(const Attitude& a) {
  const double cr = std::cos(a.roll_deg * kDeg), sr = std::sin(a.roll_deg * kDeg);
  const double cp = std::cos(a.pitch_deg * kDeg), sp = std::sin(a.pitch_deg * kDeg);
  const double cy = std::cos(a.yaw_deg * kDeg), sy = std::sin(a.yaw_deg * kDeg);
  Eigen::Matrix3d Rz, Ry, Rx;
  Rz << cy, -sy, 0, sy, cy, 0, 0, 0, 1;
  Ry << cp, 0, sp, 0, 1, 0, -sp, 0, cp;
  Rx << 1, 0, 0, 0, cr, -sr, 0, sr, cr;
  return Rz * Ry * Rx;  // docs/conventions.md; seed 002 eq. 3 with φ = yaw, θ = pitch, ψ = roll
}

Attitude attitude_from_quaternion(double w, double x, double y, double z) {
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  if (!(n > 0)) return Attitude{};
  w /= n, x /= n, y /= n, z /= n;
  // The body → NED rotation matrix of a unit Hamilton quaternion has
  //   R00 = 1 − 2(y² + z²), R10 = 2(xy + wz), R20 = 2(xz − wy), R21 = 2(yz + wx), R22 = 1 − 2(x² + y²),
  // and Rz(yaw)·Ry(pitch)·Rx(roll) has R00 = cos yaw cos pitch, R10 = sin yaw cos pitch,
  // R20 = −sin pitch, R21 = cos pitch sin roll, R22 = cos pitch cos roll. Hence
  //   roll = atan2(R21, R22), pitch = asin(−R20), yaw = atan2(R10, R00),
  // the 3-2-1 (yaw-pitch-roll) conversion of Wikipedia, "Conversion between quaternions and Euler
  // angles", section "Quaternion to Euler angles (in 3-2-1 sequence) conversion". asin's argument
  // is clamped against rounding past ±1.
  Attitude a;
  a.roll_deg = std::atan2(2 * (y * z + w * x), 1 - 2 * (x * x + y * y)) / kDeg;
  a.pitch_deg = std::asin(std::clamp(2 * (w * y - x * z), -1.0, 1.0)) / kDeg;
  a.yaw_deg = wrap_deg_180(std::atan2(2 * (x * y + w * z), 1 - 2 * (y * y + z * z)) / kDeg);
  return a;
}

}  // namespace rangecal
