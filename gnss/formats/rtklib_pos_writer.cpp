#include "gnss/formats/rtklib_pos_writer.hpp"

#include <algorithm>

#include "config/atomic_file.hpp"
#include "config/number_format.hpp"

namespace rangecal {
namespace {

constexpr std::int64_t kGpsEpochUnixNs = 315964800LL * kNsPerSecond;  // 1980-01-06 on the Unix scale
constexpr std::int64_t kNsPerWeek = 604800LL * kNsPerSecond;

std::int64_t floor_div_pos(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

// `(weekNNNN TOW s)` part of the obs start/end lines: always GPST, %8.1f seconds of week.
std::string week_tow_text(GpsTime t) {
  const std::int64_t week = floor_div_pos(t.ns, kNsPerWeek);
  const double tow = static_cast<double>(t.ns - week * kNsPerWeek) * 1e-9;
  return fmt::format("(week{:04} {:>8.1f}s)", static_cast<int>(week), tow);
}

}  // namespace

std::string format_gpst_calendar(GpsTime t, int decimals) {
  decimals = std::clamp(decimals, 0, 9);
  std::int64_t unit = 1;
  for (int i = decimals; i < 9; ++i) unit *= 10;
  // Round to the last printed digit (RTKLIB's time2str rounds, it does not truncate).
  const std::int64_t rounded = floor_div_pos(t.ns + unit / 2, unit) * unit;
  // The GPST calendar reading is the calendar of GPS seconds counted from 1980-01-06 without
  // leap seconds, i.e. a UTC-formatter applied to the shifted count.
  const std::string iso = format_iso8601_utc(UtcTime{rounded + kGpsEpochUnixNs}, decimals);
  // iso: YYYY-MM-DDThh:mm:ss[.fff]Z → YYYY/MM/DD hh:mm:ss[.fff]
  std::string s = iso.substr(0, iso.size() - 1);
  s[4] = '/';
  s[7] = '/';
  s[10] = ' ';
  return s;
}

std::string format_rtklib_pos_line(const PosWriterEpoch& e) {
  // postpos.c/solution.c outsolllh: time, then each field preceded by the one-space separator.
  return format_gpst_calendar(e.time, 3) +
         fmt::format(
             " {:>14.9f} {:>14.9f} {:>10.4f} {:3} {:3} {:>8.4f} {:>8.4f} {:>8.4f} {:>8.4f} {:>8.4f} "
             "{:>8.4f} {:>6.2f} {:>6.1f}",
             e.lat_deg, e.lon_deg, e.h_m, e.quality, e.satellites, e.sdn_m, e.sde_m, e.sdu_m, e.sdne_m,
             e.sdeu_m, e.sdun_m, e.age_s, std::min(e.ratio, 999.9));
}

std::string format_rtklib_pos(const PosWriterHeader& header, const std::vector<PosWriterEpoch>& epochs) {
  std::string s;
  s += "% program   : " + header.program + "\n";
  for (const auto& f : header.input_files) s += "% inp file  : " + f + "\n";
  if (!epochs.empty() || (header.obs_start && header.obs_end)) {
    const GpsTime t0 = header.obs_start ? *header.obs_start : epochs.front().time;
    const GpsTime t1 = header.obs_end ? *header.obs_end : epochs.back().time;
    s += "% obs start : " + format_gpst_calendar(t0, 1) + " GPST " + week_tow_text(t0) + "\n";
    s += "% obs end   : " + format_gpst_calendar(t1, 1) + " GPST " + week_tow_text(t1) + "\n";
  }
  if (header.has_ref_pos)
    s += fmt::format("% ref pos   :{:>13.9f} {:>14.9f} {:>10.4f}\n", header.ref_lat_deg, header.ref_lon_deg,
                     header.ref_h_m);
  s += "%\n";
  s += "% (lat/lon/height=WGS84/ellipsoidal,Q=1:fix,2:float,3:sbas,4:dgps,5:single,6:ppp,ns=# of "
       "satellites)\r\n";
  s += "%  GPST                  latitude(deg) longitude(deg)  height(m)   Q  ns   sdn(m)   sde(m)   sdu(m)  "
       "sdne(m)  sdeu(m)  sdun(m) age(s)  ratio\r\n";
  for (const auto& e : epochs) s += format_rtklib_pos_line(e) + "\r\n";
  return s;
}

void write_rtklib_pos(const std::string& path, const PosWriterHeader& header,
                      const std::vector<PosWriterEpoch>& epochs) {
  write_file_atomic(path, format_rtklib_pos(header, epochs));
}

}  // namespace rangecal
