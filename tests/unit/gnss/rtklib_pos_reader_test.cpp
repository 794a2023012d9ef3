// RTKLIB .pos reader against the real solutions in external/gnss/pos (SOURCE.md documents what
// each file holds) and against hand-made bad inputs.
#include "gnss/formats/rtklib_pos_reader.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "config/error.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

using test::external;

std::string pos_path(const std::string& name) {
  return external("gnss/pos/" + name).string();
}

const PosFile& cached(const std::string& name) {
  static std::map<std::string, PosFile> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, read_rtklib_pos(pos_path(name))).first;
  return it->second;
}

TEST(RtklibPosReader, EveryRealFileParsesWithItsHeaderRead) {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(external("gnss/pos"))) {
    if (entry.path().extension() != ".pos") continue;
    const PosFile f = read_rtklib_pos(entry.path().string());
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    ++n;
    const bool single = name.find("single") != std::string::npos;
    // SOURCE.md §2: every kinematic file holds the same 1878 epochs; the single run is 2 min at 1 Hz.
    if (single) {
      EXPECT_EQ(f.epochs.size(), 121u);
      EXPECT_FALSE(f.header.ref_pos_ecef.has_value());  // no `ref pos` line in single mode
      for (const PosEpoch& e : f.epochs) EXPECT_EQ(e.quality, 5);
    } else {
      EXPECT_EQ(f.epochs.size(), 1878u);
      EXPECT_TRUE(f.header.ref_pos_ecef.has_value());
    }
    const auto expect_sys = name.find("_utc") != std::string::npos   ? PosTimeSystem::utc
                            : name.find("_jst") != std::string::npos ? PosTimeSystem::jst
                                                                     : PosTimeSystem::gpst;
    EXPECT_EQ(f.header.time_system, expect_sys);
    EXPECT_EQ(f.header.time_format,
              name.find("weektow") != std::string::npos ? PosTimeFormat::week_tow : PosTimeFormat::calendar);
    const auto expect_fmt = name.find("_xyz") != std::string::npos   ? PosPositionFormat::ecef
                            : name.find("_enu") != std::string::npos ? PosPositionFormat::enu_baseline
                            : name.find("_dms") != std::string::npos ? PosPositionFormat::llh_dms
                                                                     : PosPositionFormat::llh_deg;
    EXPECT_EQ(f.header.position_format, expect_fmt);
    EXPECT_EQ(f.header.has_velocity, name.find("_vel") != std::string::npos);
    for (std::size_t i = 1; i < f.epochs.size(); ++i) ASSERT_LT(f.epochs[i - 1].utc, f.epochs[i].utc);
  }
  EXPECT_EQ(n, 9);
}

TEST(RtklibPosReader, QualityCountsMatchSourceMd) {
  std::map<int, int> q;
  for (const PosEpoch& e : cached("rover20181009_kin_llh_gpst.pos").epochs) ++q[e.quality];
  EXPECT_EQ(q[1], 444);
  EXPECT_EQ(q[2], 1434);
  EXPECT_EQ(q.size(), 2u);
}

TEST(RtklibPosReader, GpstIsUtcPlus18sAndFirstEpochIsExact) {
  const PosFile& g = cached("rover20181009_kin_llh_gpst.pos");
  const PosFile& u = cached("rover20181009_kin_llh_utc.pos");
  // SOURCE.md §5: 12:22:11.000 GPST = 12:21:53.000 UTC.
  EXPECT_EQ(g.epochs.front().utc, utc_from_civil(2018, 10, 9, 12, 21, 53, 0));
  ASSERT_EQ(g.epochs.size(), u.epochs.size());
  for (std::size_t i = 0; i < g.epochs.size(); ++i) {
    // Same instant after conversion: the GPST file's printed time is the UTC file's + 18 s.
    ASSERT_EQ(g.epochs[i].utc, u.epochs[i].utc) << i;
    ASSERT_EQ(g.epochs[i].position, u.epochs[i].position) << i;
  }
}

TEST(RtklibPosReader, JstIsUtcPlusNineHours) {
  const PosFile& j = cached("rover20181009_kin_llh_jst_opts_vel.pos");
  const PosFile& u = cached("rover20181009_kin_llh_utc.pos");
  // The JST file's first line prints 21:21:53.000 = 12:21:53.000 UTC.
  EXPECT_EQ(j.epochs.front().utc, utc_from_civil(2018, 10, 9, 12, 21, 53, 0));
  ASSERT_EQ(j.epochs.size(), u.epochs.size());
  for (std::size_t i = 0; i < j.epochs.size(); ++i) ASSERT_EQ(j.epochs[i].utc, u.epochs[i].utc) << i;
}

TEST(RtklibPosReader, WeekTowEqualsCalendarExactly) {
  const PosFile& w = cached("rover20181009_kin_llh_weektow.pos");
  const PosFile& g = cached("rover20181009_kin_llh_gpst.pos");
  ASSERT_EQ(w.epochs.size(), g.epochs.size());
  for (std::size_t i = 0; i < w.epochs.size(); ++i) {
    ASSERT_EQ(w.epochs[i].utc, g.epochs[i].utc) << i;
    ASSERT_EQ(w.epochs[i].position, g.epochs[i].position) << i;
  }
  // Week 2022 TOW 217331.000 is the first epoch (SOURCE.md §5).
  EXPECT_EQ(w.epochs.front().utc, gps_to_utc(gps_from_week_tow(2022, 217331LL * kNsPerSecond)));
}

TEST(RtklibPosReader, OffSecondTagsAreKeptToTheMillisecond) {
  // SOURCE.md §5: two tags at 12:31:42.999 and 12:31:43.999 GPST.
  int off = 0;
  for (const PosEpoch& e : cached("rover20181009_kin_llh_gpst.pos").epochs)
    if (e.utc.ns % kNsPerSecond != 0) {
      ++off;
      EXPECT_EQ(e.utc.ns % kNsPerSecond, 999000000);
    }
  EXPECT_EQ(off, 2);
  const UtcTime t = gps_to_utc(gps_from_civil(2018, 10, 9, 12, 31, 42, 999000000));
  bool found = false;
  for (const PosEpoch& e : cached("rover20181009_kin_llh_gpst.pos").epochs) found |= e.utc == t;
  EXPECT_TRUE(found);
}

TEST(RtklibPosReader, DmsEqualsDegreesWithinPrintRounding) {
  const PosFile& d = cached("rover20181009_kin_dms_gpst.pos");
  const PosFile& g = cached("rover20181009_kin_llh_gpst.pos");
  ASSERT_EQ(d.epochs.size(), g.epochs.size());
  // d m s prints seconds with 5 decimals (±0.5e-5″ = ±1.39e-9°), degrees with 9 (±0.5e-9°).
  const double tol = 0.5e-5 / 3600 + 0.5e-9 + 1e-13;
  double worst = 0;
  for (std::size_t i = 0; i < d.epochs.size(); ++i) {
    ASSERT_EQ(d.epochs[i].utc, g.epochs[i].utc);
    for (int k = 0; k < 2; ++k)
      worst = std::max(worst, std::abs(d.epochs[i].position[k] - g.epochs[i].position[k]));
    ASSERT_EQ(d.epochs[i].position[2], g.epochs[i].position[2]);
    // Same covariance (the DMS header's mislabelled n-u column is still the n-u term).
    ASSERT_EQ(d.epochs[i].covariance, g.epochs[i].covariance);
  }
  EXPECT_LE(worst, tol);
  EXPECT_LT(d.epochs.front().position[1], 0);  // western longitude keeps its sign
}

TEST(RtklibPosReader, SignedSqrtCrossTermsAndColumnOrder) {
  // First data line of the llh file: sdn 0.7016 sde 0.5847 sdu 1.1912 sdne 0.4352 sdeu -0.2165 sdun -0.4174.
  const PosEpoch& e = cached("rover20181009_kin_llh_gpst.pos").epochs.front();
  EXPECT_DOUBLE_EQ(e.covariance(0, 0), 0.5847 * 0.5847);   // E
  EXPECT_DOUBLE_EQ(e.covariance(1, 1), 0.7016 * 0.7016);   // N
  EXPECT_DOUBLE_EQ(e.covariance(2, 2), 1.1912 * 1.1912);   // U
  EXPECT_DOUBLE_EQ(e.covariance(0, 1), 0.4352 * 0.4352);   // EN
  EXPECT_DOUBLE_EQ(e.covariance(0, 2), -0.2165 * 0.2165);  // EU
  EXPECT_DOUBLE_EQ(e.covariance(1, 2), -0.4174 * 0.4174);  // NU
  EXPECT_EQ(e.quality, 2);
  EXPECT_EQ(e.ns, 14);
  EXPECT_DOUBLE_EQ(e.age_s, 3.99);
  EXPECT_DOUBLE_EQ(e.ratio, 1.1);
  EXPECT_DOUBLE_EQ(e.position[0], 53.282679913);
  EXPECT_DOUBLE_EQ(e.position[1], -8.982172753);
  EXPECT_DOUBLE_EQ(e.position[2], 89.1645);
  // The ENU file orders its terms sde sdn sdu sden sdnu sdue: the same covariance must come out.
  const PosEpoch& b = cached("rover20181009_kin_enu_gpst.pos").epochs.front();
  EXPECT_EQ(b.covariance, e.covariance);
  // ECEF: sdx sdy sdz sdxy sdyz sdzx = 0.9588 0.6427 0.9596 -0.5207 -0.0488 0.7068.
  const PosEpoch& x = cached("rover20181009_kin_xyz_gpst.pos").epochs.front();
  EXPECT_DOUBLE_EQ(x.covariance(0, 1), -0.5207 * 0.5207);
  EXPECT_DOUBLE_EQ(x.covariance(1, 2), -0.0488 * 0.0488);
  EXPECT_DOUBLE_EQ(x.covariance(2, 0), 0.7068 * 0.7068);
  EXPECT_DOUBLE_EQ(x.position[0], 3774698.1018);
}

TEST(RtklibPosReader, VelocityColumns) {
  // vn 0.00101 ve -0.01245 vu -0.00754 sdvn 0.12172 sdve 0.11588 sdvu 0.24536 sdvne 0.06873 sdveu -0.03615
  // sdvun -0.10166 on the first line.
  const PosEpoch& e = cached("rover20181009_kin_llh_gpst_opts_vel.pos").epochs.front();
  ASSERT_TRUE(e.has_velocity);
  EXPECT_DOUBLE_EQ(e.velocity[0], -0.01245);
  EXPECT_DOUBLE_EQ(e.velocity[1], 0.00101);
  EXPECT_DOUBLE_EQ(e.velocity[2], -0.00754);
  EXPECT_DOUBLE_EQ(e.velocity_covariance(0, 0), 0.11588 * 0.11588);
  EXPECT_DOUBLE_EQ(e.velocity_covariance(1, 1), 0.12172 * 0.12172);
  EXPECT_DOUBLE_EQ(e.velocity_covariance(0, 1), 0.06873 * 0.06873);
  EXPECT_DOUBLE_EQ(e.velocity_covariance(0, 2), -0.03615 * 0.03615);
  EXPECT_DOUBLE_EQ(e.velocity_covariance(1, 2), -0.10166 * 0.10166);
  // Same positions as the plain file.
  EXPECT_EQ(e.position, cached("rover20181009_kin_llh_gpst.pos").epochs.front().position);
  EXPECT_FALSE(cached("rover20181009_kin_llh_gpst.pos").epochs.front().has_velocity);
}

TEST(RtklibPosReader, RefPosInEveryPrintForm) {
  // ECEF file prints the base as x/y/z; llh and dms as geodetic; all must be the same point
  // within their print rounding (0.1 mm ECEF, 1e-9 deg, 1e-5 arcsec).
  const Eigen::Vector3d x = *cached("rover20181009_kin_xyz_gpst.pos").header.ref_pos_ecef;
  const Eigen::Vector3d l = *cached("rover20181009_kin_llh_gpst.pos").header.ref_pos_ecef;
  const Eigen::Vector3d d = *cached("rover20181009_kin_dms_gpst.pos").header.ref_pos_ecef;
  EXPECT_DOUBLE_EQ(x[0], 3774696.1059);
  EXPECT_LT((x - l).norm(), 0.3e-3);
  EXPECT_LT((x - d).norm(), 0.3e-3);
}

TEST(RtklibPosReader, LfOnlyAndCrlfGiveTheSameEpochs) {
  std::string text = test::read_text(pos_path("rover20181009_kin_llh_gpst.pos"));
  std::string lf;
  for (char c : text)
    if (c != '\r') lf += c;
  const PosFile a = parse_rtklib_pos(lf, "lf.pos");
  const PosFile& b = cached("rover20181009_kin_llh_gpst.pos");
  ASSERT_EQ(a.epochs.size(), b.epochs.size());
  EXPECT_EQ(a.epochs.back().utc, b.epochs.back().utc);
  EXPECT_EQ(a.epochs.back().position, b.epochs.back().position);
}

// ---- bad input: each error names the file, the line and the field ----

// The llh file's header (11 lines) plus `data` lines.
std::string llh_file_with(const std::string& data) {
  const std::string text = test::read_text(pos_path("rover20181009_kin_llh_gpst.pos"));
  std::size_t pos = 0;
  for (int i = 0; i < 11; ++i) pos = text.find('\n', pos) + 1;
  return text.substr(0, pos) + data;
}

const char* kLine1 =
    "2018/10/09 12:22:11.000   53.282679913   -8.982172753    89.1645   2  14   0.7016   0.5847   1.1912   "
    "0.4352  "
    "-0.2165  -0.4174   3.99    1.1\r\n";
const char* kLine2 =
    "2018/10/09 12:22:12.000   53.282679876   -8.982173019    89.2251   2  14   0.5010   0.4165   0.8481   "
    "0.3110  "
    "-0.1540  -0.2960   4.99    1.1\r\n";

Error expect_error(const std::string& content, const std::string& name) {
  const auto path = test::scratch_dir("pos_bad_" + name) / (name + ".pos");
  test::write_text(path, content);
  try {
    read_rtklib_pos(path.string());
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_EQ(e.file(), path.string());
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    if (e.line() > 0) {
      EXPECT_NE(what.find(":" + std::to_string(e.line())), std::string::npos) << what;
    }
    if (!e.field().empty()) {
      EXPECT_NE(what.find(e.field()), std::string::npos) << what;
    }
    return e;
  }
  ADD_FAILURE() << "no error for " << name;
  return Error(ErrorKind::usage, "", 0, "", "");
}

TEST(RtklibPosReaderBadInput, SanityTheGoodLinesParse) {
  const auto path = test::scratch_dir("pos_good") / "good.pos";
  test::write_text(path, llh_file_with(std::string(kLine1) + kLine2));
  EXPECT_EQ(read_rtklib_pos(path.string()).epochs.size(), 2u);
}

TEST(RtklibPosReaderBadInput, TruncatedLine) {
  const Error e =
      expect_error(llh_file_with(std::string(kLine1) +
                                 "2018/10/09 12:22:12.000   53.282679876   -8.982173019    89.2251   2\r\n"),
                   "truncated");
  EXPECT_EQ(e.line(), 13);
  EXPECT_EQ(e.field(), "ns");
  EXPECT_NE(e.reason().find("truncated"), std::string::npos);
}

TEST(RtklibPosReaderBadInput, NonNumericField) {
  std::string l2 = kLine2;
  l2.replace(l2.find("89.2251"), 7, "89.2x51");
  const Error e = expect_error(llh_file_with(kLine1 + l2), "nonnumeric");
  EXPECT_EQ(e.line(), 13);
  EXPECT_EQ(e.field(), "height(m)");
  EXPECT_NE(e.reason().find("89.2x51"), std::string::npos);
}

TEST(RtklibPosReaderBadInput, QualityOutsideOneToSix) {
  std::string l2 = kLine2;
  l2.replace(l2.find("   2  14"), 8, "   7  14");
  const Error e = expect_error(llh_file_with(kLine1 + l2), "q7");
  EXPECT_EQ(e.line(), 13);
  EXPECT_EQ(e.field(), "Q");
  EXPECT_NE(e.reason().find("1-6"), std::string::npos);
}

TEST(RtklibPosReaderBadInput, TimeGoingBackwardsOrRepeating) {
  Error e = expect_error(llh_file_with(std::string(kLine2) + kLine1), "backwards");
  EXPECT_EQ(e.line(), 13);
  EXPECT_EQ(e.field(), "GPST");
  EXPECT_NE(e.reason().find("strictly increasing"), std::string::npos);
  e = expect_error(llh_file_with(std::string(kLine1) + kLine1), "repeat");
  EXPECT_EQ(e.line(), 13);
  EXPECT_EQ(e.field(), "GPST");
}

TEST(RtklibPosReaderBadInput, NoEpochs) {
  const Error e = expect_error(llh_file_with(""), "noepochs");
  EXPECT_EQ(e.line(), 11);
  EXPECT_EQ(e.field(), "epochs");
  const Error e2 = expect_error("", "empty");
  EXPECT_EQ(e2.field(), "epochs");
}

TEST(RtklibPosReaderBadInput, MissingFile) {
  const std::string path = (test::scratch_dir("pos_missing") / "nope.pos").string();
  try {
    read_rtklib_pos(path);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), path);
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
}

TEST(RtklibPosReaderBadInput, UnknownColumnHeader) {
  std::string text = llh_file_with(kLine1);
  text.replace(text.find("%  GPST"), 7, "%  GPSX");
  Error e = expect_error(text, "badtime");
  EXPECT_EQ(e.line(), 11);
  EXPECT_EQ(e.field(), "GPSX");
  text = llh_file_with(kLine1);
  text.replace(text.find("latitude(deg)"), 13, "latitude(rad)");
  e = expect_error(text, "badpos");
  EXPECT_EQ(e.line(), 11);
  EXPECT_EQ(e.field(), "latitude(rad)");
  text = llh_file_with(kLine1);
  text.replace(text.find("sdun(m)"), 7, "sdxx(m)");
  e = expect_error(text, "badsd");
  EXPECT_EQ(e.field(), "sdxx(m)");
}

TEST(RtklibPosReaderBadInput, BadCalendarAndExtraField) {
  std::string l2 = kLine2;
  l2.replace(0, 10, "2018/13/09");
  Error e = expect_error(llh_file_with(kLine1 + l2), "baddate");
  EXPECT_EQ(e.line(), 13);
  EXPECT_EQ(e.field(), "GPST (date or week)");
  l2 = kLine2;
  l2.insert(l2.size() - 2, "  5.0");
  e = expect_error(llh_file_with(kLine1 + l2), "extra");
  EXPECT_EQ(e.line(), 13);
}

// Fuzzing found these (docs/reliability.md "Fuzzing"): a year or GPS week whose time in int64 ns
// overflows (undefined behaviour) was accepted; dates outside 1970-2200 are refused
// (supported_civil_year, utc_time.hpp).
TEST(RtklibPosReaderBadInput, YearOrWeekOutsideTheRepresentableRangeIsAnError) {
  for (const char* year : {"0219", "1969", "2201", "9999"}) {
    std::string l1 = kLine1;
    l1.replace(0, 4, year);
    const Error e = expect_error(llh_file_with(l1), std::string("year") + year);
    EXPECT_EQ(e.line(), 12);
    EXPECT_EQ(e.field(), "GPST (date or week)");
    EXPECT_NE(e.reason().find("1970-2200"), std::string::npos) << e.what();
  }
  const std::string text = test::read_text(pos_path("rover20181009_kin_llh_weektow.pos"));
  std::size_t pos = 0;
  for (int i = 0; i < 11; ++i) pos = text.find('\n', pos) + 1;
  for (const char* week : {"11531", "99999"}) {
    std::string l1 = text.substr(pos, text.find('\n', pos) + 1 - pos);
    l1.replace(0, 4, week);
    const Error e = expect_error(text.substr(0, pos) + l1, std::string("week") + week);
    EXPECT_EQ(e.line(), 12);
    EXPECT_EQ(e.field(), "GPST (date or week)");
  }
  // A time of week whose ns overflow an int64 (UBSan, found by fuzz_rtklib_pos with CI's seed).
  for (const char* tow : {"21733217331.0", "9223372036.000"}) {
    std::string l1 = text.substr(pos, text.find('\n', pos) + 1 - pos);
    const std::size_t start = l1.find_first_not_of(' ', l1.find(' '));
    l1.replace(start, l1.find(' ', start) - start, tow);
    const Error e = expect_error(text.substr(0, pos) + l1, std::string("tow") + tow);
    EXPECT_EQ(e.line(), 12);
    EXPECT_NE(e.reason().find("time of week"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rangecal
