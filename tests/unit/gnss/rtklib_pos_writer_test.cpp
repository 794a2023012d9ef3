// The .pos writer against real RTKLIB 2.4.3 output: every epoch of a real solution, parsed here
// independently and written back, must reproduce the real file byte for byte (header lines,
// column widths, mixed LF/CRLF line endings).
#include "gnss/formats/rtklib_pos_writer.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "support/paths.hpp"

namespace rangecal {
namespace {

// "2018/10/09 12:22:11.000" (any number of decimals) → GpsTime, parsed with sscanf.
GpsTime parse_calendar(const std::string& text) {
  int y, mo, d, h, mi, s;
  char frac[16] = "";
  const int n = std::sscanf(text.c_str(), "%d/%d/%d %d:%d:%d.%15[0-9]", &y, &mo, &d, &h, &mi, &s, frac);
  EXPECT_GE(n, 6) << text;
  std::string f(frac);
  while (f.size() < 9) f += '0';
  return gps_from_civil(y, mo, d, h, mi, s, std::stoll(f));
}

struct ParsedPos {
  PosWriterHeader header;
  std::vector<PosWriterEpoch> epochs;
};

ParsedPos parse_real_pos(const std::string& text) {
  ParsedPos p;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.rfind("% program   : ", 0) == 0) {
      p.header.program = line.substr(14);
    } else if (line.rfind("% inp file  : ", 0) == 0) {
      p.header.input_files.push_back(line.substr(14));
    } else if (line.rfind("% obs start : ", 0) == 0) {
      p.header.obs_start = parse_calendar(line.substr(14));
    } else if (line.rfind("% obs end   : ", 0) == 0) {
      p.header.obs_end = parse_calendar(line.substr(14));
    } else if (line.rfind("% ref pos   :", 0) == 0) {
      p.header.has_ref_pos = true;
      EXPECT_EQ(std::sscanf(line.c_str() + 13, "%lf %lf %lf", &p.header.ref_lat_deg, &p.header.ref_lon_deg,
                            &p.header.ref_h_m),
                3);
    } else if (!line.empty() && line[0] != '%') {
      PosWriterEpoch e;
      e.time = parse_calendar(line.substr(0, 23));
      const int n = std::sscanf(line.c_str() + 23, "%lf %lf %lf %d %d %lf %lf %lf %lf %lf %lf %lf %lf",
                                &e.lat_deg, &e.lon_deg, &e.h_m, &e.quality, &e.satellites, &e.sdn_m, &e.sde_m,
                                &e.sdu_m, &e.sdne_m, &e.sdeu_m, &e.sdun_m, &e.age_s, &e.ratio);
      EXPECT_EQ(n, 13) << line;
      p.epochs.push_back(e);
    }
  }
  return p;
}

void expect_round_trip(const std::string& name) {
  const std::string real = test::read_text(test::external("gnss/pos/" + name));
  const ParsedPos p = parse_real_pos(real);
  ASSERT_GT(p.epochs.size(), 10u);
  const std::string ours = format_rtklib_pos(p.header, p.epochs);
  ASSERT_EQ(ours.size(), real.size()) << name;
  // Report the first differing line rather than two megabyte strings.
  std::size_t i = 0;
  while (i < ours.size() && ours[i] == real[i]) ++i;
  if (i < ours.size()) {
    const std::size_t a = real.rfind('\n', i) + 1;
    FAIL() << name << ": first difference at byte " << i
           << "\nreal: " << real.substr(a, real.find('\n', i) - a)
           << "\nours: " << ours.substr(a, ours.find('\n', i) - a);
  }
}

TEST(RtklibPosWriter, ReproducesRealKinematicFileByteForByte) {
  expect_round_trip("rover20181009_kin_llh_gpst.pos");
}

TEST(RtklibPosWriter, ReproducesRealSingleFileWithoutRefPos) {
  expect_round_trip("rover20181009_single_llh_gpst_2min.pos");
}

TEST(RtklibPosWriter, LineEndingsAreLfThenCrlf) {
  PosWriterHeader h;
  h.input_files = {"a.obs"};
  PosWriterEpoch e;
  e.time = gps_from_civil(2026, 5, 14, 2, 30, 18, 0);
  const std::string s = format_rtklib_pos(h, {e});
  // program, inp file, obs start, obs end, "%": LF only; legend, column header, data: CRLF.
  EXPECT_EQ(s.find("\r"),
            s.find("% (lat/lon/height") + std::string("% (lat/lon/height=WGS84/ellipsoidal,Q=1:fix,2:"
                                                      "float,3:sbas,4:dgps,5:single,6:ppp,ns=# of "
                                                      "satellites)")
                                              .size());
  EXPECT_NE(s.find("% obs start : 2026/05/14 02:30:18.0 GPST (week2418 354618.0s)\n"), std::string::npos)
      << s;
  EXPECT_NE(s.find("\r\n2026/05/14 02:30:18.000 "), std::string::npos);
  EXPECT_EQ(s.substr(s.size() - 2), "\r\n");
}

TEST(RtklibPosWriter, CalendarRoundsToTheLastDigit) {
  const GpsTime t = gps_from_civil(2026, 12, 31, 23, 59, 59, 999600000);
  EXPECT_EQ(format_gpst_calendar(t, 3), "2027/01/01 00:00:00.000");  // rounds, carrying into the year
  EXPECT_EQ(format_gpst_calendar(t, 1), "2027/01/01 00:00:00.0");
  EXPECT_EQ(format_gpst_calendar(gps_from_civil(2026, 1, 2, 3, 4, 5, 123400000), 3),
            "2026/01/02 03:04:05.123");
}

}  // namespace
}  // namespace rangecal
