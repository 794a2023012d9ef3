#pragma once
// Writes PPK solutions as RTKLIB 2.4.3 rnx2rtkp writes them (docs/formats.md; external/gnss/SOURCE.md
// §4): `%` header lines (program, input files, obs start/end, ref pos, `%`, legend, column
// header), then one epoch a line in GPST calendar time (`yyyy/mm/dd hh:mm:ss.sss`) with
// lat/lon in degrees (%14.9f), ellipsoidal height (%10.4f), Q, ns, sdn sde sdu sdne sdeu sdun
// (%8.4f; the cross terms are signed square roots of the covariances), age (%6.2f) and ratio
// (%6.1f). Line endings are RTKLIB's mixed ones: the first header lines end in LF, the legend,
// the column header and every data line in CRLF. Used by the simulator (docs/simulator.md).
#include <optional>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"

namespace rangecal {

/// One epoch as rnx2rtkp prints it.
struct PosWriterEpoch {
  GpsTime time;                               ///< epoch time (GPST); printed rounded to the millisecond
  double lat_deg = 0;                         ///< WGS84 latitude, degrees
  double lon_deg = 0;                         ///< WGS84 longitude, degrees
  double h_m = 0;                             ///< ellipsoidal height, metres
  int quality = 1;                            ///< Q: 1 fix, 2 float, 3 sbas, 4 dgps, 5 single, 6 ppp
  int satellites = 0;                         ///< ns
  double sdn_m = 0, sde_m = 0, sdu_m = 0;     ///< 1σ north, east, up (m)
  double sdne_m = 0, sdeu_m = 0, sdun_m = 0;  ///< signed square roots of the covariances (m)
  double age_s = 0;                           ///< differential age (s)
  double ratio = 0;                           ///< ambiguity ratio (capped at 999.9 as RTKLIB does)
};

/// Header content. `input_files` become `% inp file  :` lines; the obs start/end lines give the
/// first and last rover observation epoch (`obs_start`/`obs_end`, defaulting to the first and
/// last solution epoch; both lines omitted when there is neither); `ref_pos` (lat deg, lon deg,
/// h m) gives the `% ref pos   :` line when `has_ref_pos`.
struct PosWriterHeader {
  std::string program = "rnx2rtkp ver.2.4.3 b34";
  std::vector<std::string> input_files;
  std::optional<GpsTime> obs_start, obs_end;
  bool has_ref_pos = false;
  double ref_lat_deg = 0, ref_lon_deg = 0, ref_h_m = 0;
};

/// The whole file's text (LF and CRLF line endings as RTKLIB writes them). Epochs are written in
/// the given order. The time system is GPST, the time form calendar with 3 decimals.
std::string format_rtklib_pos(const PosWriterHeader& header, const std::vector<PosWriterEpoch>& epochs);

/// One data line without its line ending, e.g.
/// `2018/10/09 12:22:11.000   53.282679913   -8.982172753    89.1645   2  14   0.7016 …    1.1`.
std::string format_rtklib_pos_line(const PosWriterEpoch& epoch);

/// The GPST calendar text `yyyy/mm/dd hh:mm:ss.sss` (`decimals` 0–9 fraction digits, rounded
/// to the nearest unit of the last digit, as RTKLIB's time2str rounds).
std::string format_gpst_calendar(GpsTime t, int decimals);

/// Writes format_rtklib_pos(...) to `path` atomically (config/atomic_file.hpp).
void write_rtklib_pos(const std::string& path, const PosWriterHeader& header,
                      const std::vector<PosWriterEpoch>& epochs);

}  // namespace rangecal
