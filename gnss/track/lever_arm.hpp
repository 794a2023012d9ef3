#pragma once
// Lever arm (docs/conventions.md, docs/formats.md; seed 002 §2.2–2.3): from the antenna phase centre to the
// lamp centre.
//  - full form: the lever is a body FRD vector (m); lamp_NED = antenna_NED + R_nb·lever
//    (seed 002 eq. 4), then NED → ENU;
//  - vertical form (seed 002 eq. 5): the lamp is `vertical_m` straight below the antenna; exact
//    only at zero roll and pitch with the lever along the body z axis (seeds/NOTES.md);
//  - total-station file `session,target,E,N,U` (targets `antenna`, `lamp`, marks at the heights
//    of the two centres, seed 002 §2.3): vertical_m = mean over sessions of U(antenna) − U(lamp),
//    with its sample sd.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "gnss/track/attitude.hpp"

namespace rangecal {

/// NED (north, east, down) ↔ ENU (east, north, up) vector components.
inline Eigen::Vector3d ned_to_enu(const Eigen::Vector3d& ned) {
  return {ned[1], ned[0], -ned[2]};
}
inline Eigen::Vector3d enu_to_ned(const Eigen::Vector3d& enu) {
  return {enu[1], enu[0], -enu[2]};
}

/// Full form: lamp ENU (m) from antenna ENU (m), R_nb (v_NED = R_nb·v_FRD) and the lever in body
/// FRD (m): lamp = antenna + ENU(R_nb·lever).
Eigen::Vector3d lamp_enu_full(const Eigen::Vector3d& antenna_enu, const Eigen::Matrix3d& R_nb,
                              const Eigen::Vector3d& lever_frd_m);

/// Vertical form (seed 002 eq. 5): the lamp is `vertical_m` below the antenna (U decreases).
Eigen::Vector3d lamp_enu_vertical(const Eigen::Vector3d& antenna_enu, double vertical_m);

/// How far the vertical form is from the full form with lever (0, 0, vertical_m) at attitude
/// R_nb: |R_nb·(0,0,d) − (0,0,d)| = |d|·√(2 − 2·cos(tilt)), metres.
double vertical_form_error_m(const Eigen::Matrix3d& R_nb, double vertical_m);

/// How fast a body-frame lever arm turns with the UAV at `t`: |d/dt (R_nb·lever)| (m/s, i.e. mm of
/// lamp displacement per ms of attitude time error; docs/gnss.md "Receiver lag"), by a central
/// difference over ±20 ms of the interpolated attitude. None where the attitude does not cover
/// t ± 20 ms (gaps over `max_gap_s` are not bridged, as interpolate_attitude).
std::optional<double> lever_motion_mps(const AttitudeSeries& att, UtcTime t,
                                       const Eigen::Vector3d& lever_frd_m, double max_gap_s);

/// The vertical offset measured with a total station (docs/formats.md).
struct TotalStationOffset {
  double vertical_m = 0;              ///< mean over sessions of U(antenna) − U(lamp), m
  double sd_m = 0;                    ///< sample sd of the per-session values (n − 1); 0 with one session
  std::vector<std::string> sessions;  ///< session ids, in file order
  std::vector<double> per_session_m;  ///< U(antenna) − U(lamp) per session
};

/// Reads `session,target,E,N,U`. Every session needs exactly one `antenna` and one `lamp` row.
/// Throws rangecal::Error (input) naming file, line and column: missing file or column, unknown
/// target, a duplicate target in a session, a session lacking one target, no sessions.
TotalStationOffset read_total_station_csv(const std::string& path);
/// As read_total_station_csv, from text in memory; `path` is for messages.
TotalStationOffset parse_total_station_csv(const std::string& text, const std::string& path);

}  // namespace rangecal
