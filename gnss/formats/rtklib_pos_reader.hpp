#pragma once
// Reader of RTKLIB `.pos` solution files (docs/formats.md), as written by rnx2rtkp / RTKPOST 2.4.3 and
// the demo5 fork: `%` header lines, a column header line whose first word is the time system
// (`GPST`, `UTC` or `JST`), then one epoch per line. Every variant is read:
//   - time as `yyyy/mm/dd hh:mm:ss.sss` or `week tow` (GPS week, seconds of week);
//   - time system GPST (→ UTC by the leap-second table), UTC, or JST (UTC + 9 h);
//   - position as lat/lon/height in degrees, in d m s (6 tokens, sign on the degrees token,
//     `-0` for −1° < value < 0), ECEF x/y/z, or an e/n/u baseline about the `ref pos`;
//   - Q, ns, the six sd/cross terms (cross terms are signed square roots of covariances,
//     c = sign(v)·v²), age, ratio, and the nine velocity columns when present.
// What matters is read from the header, not guessed from column counts: the time system is the
// column header's first word, the position format comes from the column names, velocity from
// the presence of velocity column names, and `ref pos` from its header line (ECEF files print it
// as x/y/z, DMS files as d m s, the others as lat/lon/h in degrees). Line endings may be LF or
// CRLF, mixed (RTKLIB writes both in one file). Times are parsed exactly into integer ns.
//
// Errors are rangecal::Error (kind input) naming the file, the 1-based line and the column:
// missing file, unknown column header, truncated line, non-numeric field, Q outside 1–6, time
// not strictly increasing, no epochs.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

enum class PosTimeSystem { gpst, utc, jst };
enum class PosTimeFormat { calendar, week_tow };
/// How the position block of each epoch is written, hence what PosEpoch::position holds.
enum class PosPositionFormat {
  llh_deg,       ///< latitude(deg) longitude(deg) height(m)
  llh_dms,       ///< latitude(d'") longitude(d'") height(m), 3 tokens per angle
  ecef,          ///< x-ecef(m) y-ecef(m) z-ecef(m)
  enu_baseline,  ///< e/n/u-baseline(m): rover minus ref pos, in the ENU frame at ref pos
};

const char* to_string(PosTimeSystem s);
const char* to_string(PosTimeFormat f);
const char* to_string(PosPositionFormat f);

struct PosHeader {
  std::string program;  ///< `% program   :` value, may be empty
  PosTimeSystem time_system = PosTimeSystem::gpst;
  PosTimeFormat time_format = PosTimeFormat::calendar;  ///< decided by the first epoch line
  PosPositionFormat position_format = PosPositionFormat::llh_deg;
  bool has_velocity = false;
  std::vector<std::string> columns;  ///< data column names after the time system word
  long column_header_line = 0;       ///< 1-based
  /// `% ref pos :` as ECEF metres (converted from lat/lon/h or d m s when printed so), or
  /// nullopt when the header has none (single-point solutions, moving base).
  std::optional<Eigen::Vector3d> ref_pos_ecef;
};

/// One solution epoch, in the file's own frame (see PosHeader::position_format).
struct PosEpoch {
  UtcTime utc;    ///< converted from the file's time system exactly
  long line = 0;  ///< 1-based line in the file
  /// llh_deg / llh_dms: (lat deg, lon deg, ellipsoidal h m); ecef: (x, y, z) m; enu_baseline:
  /// (e, n, u) m in the ENU frame at ref pos.
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  /// Position covariance (m²), un-square-rooted from the sd columns. For llh_* the frame is the
  /// local ENU at the epoch's own position (order E, N, U); for enu_baseline the ENU frame at ref
  /// pos (E, N, U); for ecef the ECEF axes (x, y, z).
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  int quality = 0;   ///< Q: 1 fix, 2 float, 3 sbas, 4 dgps, 5 single, 6 ppp
  int ns = 0;        ///< number of satellites
  double age_s = 0;  ///< differential age (s), may be negative
  double ratio = 0;  ///< AR ratio
  bool has_velocity = false;
  /// Velocity (m/s) and its covariance ((m/s)²), when the file has velocity columns: for llh_*
  /// in local ENU (E, N, U) at the epoch, for ecef in ECEF axes.
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Matrix3d velocity_covariance = Eigen::Matrix3d::Zero();
};

struct PosFile {
  std::string path;  ///< as given, for messages
  PosHeader header;
  std::vector<PosEpoch> epochs;  ///< strictly increasing in time, ≥ 1
};

/// Reads an RTKLIB .pos file. Throws rangecal::Error (input) as described above.
PosFile read_rtklib_pos(const std::string& path);
/// Parses .pos text already in memory; `path` is used for messages only.
PosFile parse_rtklib_pos(std::string_view text, const std::string& path);

/// RTKLIB's name of a solution quality Q (RTKLIB manual, solution status): 1 fix, 2 float,
/// 3 sbas, 4 dgps, 5 single, 6 ppp; "?" for any other value.
const char* rtklib_quality_name(int q);

}  // namespace rangecal
