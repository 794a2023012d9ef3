// The gnss stage on the real PPK data: filtering counts (SOURCE.md), gaps, merging, lever arm
// forms and warnings, the lamp_track.csv round trip and run_gnss_stage end to end.
#include "pipeline/stages/gnss_stage.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "config/error.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "gnss/geodesy/local_enu.hpp"
#include "pipeline/io/output_paths.hpp"
#include "support/dataflash_writer.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

std::string pos_path(const std::string& name) {
  return test::external("gnss/pos/" + name).string();
}
const GeodeticOrigin kOrigin{53.282695790, -8.982135671, 87.4012};

const PosFile& llh() {
  static const PosFile f = read_rtklib_pos(pos_path("rover20181009_kin_llh_gpst.pos"));
  return f;
}

LampTrackInputs base_inputs(std::vector<int> accept, double max_sd = 1e9, double max_gap = 1.5) {
  LampTrackInputs in;
  in.pos_files = {llh()};
  in.origin = kOrigin;
  in.filter.accept_quality = std::move(accept);
  in.filter.max_sd_m = max_sd;
  in.filter.max_gap_s = max_gap;
  in.lever.form = ResolvedLeverArm::Form::vertical;
  in.lever.vertical_m = 0.25;
  return in;
}

TEST(GnssStage, QualityCountsOnRealData) {
  const LampTrackResult r = compute_lamp_track(base_inputs({1}));
  // SOURCE.md §5: 1878 epochs, Q=1: 444, Q=2: 1434.
  EXPECT_EQ(r.report.filter.read, 1878u);
  EXPECT_EQ(r.report.filter.kept, 444u);
  EXPECT_EQ(r.report.filter.dropped_quality, 1434u);
  EXPECT_EQ(r.report.filter.dropped_by_quality.at(2), 1434u);
  EXPECT_EQ(r.report.filter.read_by_quality.at(1), 444u);
  EXPECT_EQ(r.track.epochs.size(), 444u);
  for (const LampEpoch& e : r.track.epochs) EXPECT_EQ(e.quality, 1);
  EXPECT_EQ(compute_lamp_track(base_inputs({1, 2})).track.epochs.size(), 1878u);
}

TEST(GnssStage, SdFilterCountsAgreeWithTheFileAndAcrossFormats) {
  // Independent count straight from the printed sdn/sde/sdu columns of the Q=1|2 epochs.
  std::size_t over = 0;
  for (const PosEpoch& e : llh().epochs)
    if (e.covariance.diagonal().cwiseSqrt().maxCoeff() > 0.05) ++over;
  const LampTrackResult r = compute_lamp_track(base_inputs({1, 2}, 0.05));
  EXPECT_EQ(r.report.filter.dropped_sd, over);
  EXPECT_GT(over, 0u);
  EXPECT_EQ(r.report.filter.kept, 1878u - over);
  // The ECEF file: its covariance rotated to the local ENU gives the same decisions.
  LampTrackInputs x = base_inputs({1, 2}, 0.05);
  x.pos_files = {read_rtklib_pos(pos_path("rover20181009_kin_xyz_gpst.pos"))};
  const LampTrackResult rx = compute_lamp_track(x);
  EXPECT_NEAR(static_cast<double>(rx.report.filter.dropped_sd), static_cast<double>(over), 2.0);
}

TEST(GnssStage, GapsOfTheRealData) {
  // SOURCE.md §5: nominal 1 Hz with 14 gaps of 2–24 s.
  const LampTrackResult r = compute_lamp_track(base_inputs({1, 2}, 1e9, 1.5));
  ASSERT_EQ(r.report.gaps.size(), 14u);
  for (const TimeGap& g : r.report.gaps) {
    EXPECT_GE(g.duration_s(), 2.0 - 1e-9);
    EXPECT_LE(g.duration_s(), 24.0 + 1e-9);
  }
  EXPECT_EQ(r.report.track_start, utc_from_civil(2018, 10, 9, 12, 21, 53, 0));
  // Last line of the file: 12:54:44.000 GPST = 12:54:26.000 UTC.
  EXPECT_EQ(r.report.track_end, utc_from_civil(2018, 10, 9, 12, 54, 26, 0));
}

TEST(GnssStage, VerticalLeverLowersTheLampAndAddsTheSurveySd) {
  LampTrackInputs in = base_inputs({1, 2});
  in.lever.vertical_sd_m = 0.003;
  const LampTrackResult r = compute_lamp_track(in);
  const LocalEnu site(kOrigin);
  for (std::size_t i = 0; i < llh().epochs.size(); i += 97) {
    const EnuFix a = to_site_enu(llh(), llh().epochs[i], site);
    const LampEpoch& e = r.track.epochs[i];
    EXPECT_LT((e.enu - (a.enu - Eigen::Vector3d(0, 0, 0.25))).norm(), 1e-12);
    EXPECT_NEAR(e.sd_enu[0], std::sqrt(a.cov_enu(0, 0)), 1e-12);
    EXPECT_NEAR(e.sd_enu[2], std::sqrt(a.cov_enu(2, 2) + 0.003 * 0.003), 1e-12);
  }
}

TEST(GnssStage, SplitFilesMergeToTheSameTrackAndOverlapIsAnError) {
  const PosFile& f = llh();
  PosFile a = f, b = f;
  a.path = "a.pos";
  b.path = "b.pos";
  a.epochs.assign(f.epochs.begin(), f.epochs.begin() + 900);
  b.epochs.assign(f.epochs.begin() + 900, f.epochs.end());
  LampTrackInputs in = base_inputs({1, 2});
  in.pos_files = {b, a};  // order of the files does not matter
  const LampTrackResult merged = compute_lamp_track(in);
  const LampTrackResult whole = compute_lamp_track(base_inputs({1, 2}));
  ASSERT_EQ(merged.track.epochs.size(), whole.track.epochs.size());
  for (std::size_t i = 0; i < whole.track.epochs.size(); ++i) {
    ASSERT_EQ(merged.track.epochs[i].utc, whole.track.epochs[i].utc);
    ASSERT_EQ(merged.track.epochs[i].enu, whole.track.epochs[i].enu);
  }
  b.epochs.insert(b.epochs.begin(), f.epochs[899]);
  in.pos_files = {a, b};
  try {
    compute_lamp_track(in);
    FAIL() << "overlap accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "b.pos");
    EXPECT_NE(std::string(e.what()).find("a.pos"), std::string::npos);
  }
}

// Attitude at 10 Hz from 12:30:00 to 12:40:00 UTC with constant roll/pitch/yaw.
AttitudeSeries constant_attitude(double roll, double pitch, double yaw) {
  AttitudeSeries s;
  s.path = "att.csv";
  const UtcTime t0 = utc_from_civil(2018, 10, 9, 12, 30, 0, 0);
  for (int i = 0; i <= 6000; ++i)
    s.samples.push_back({UtcTime{t0.ns + i * 100'000'000LL}, {roll, pitch, yaw}, i + 2});
  return s;
}

TEST(GnssStage, BodyLeverDropsEpochsOutsideTheAttitudeAndRotatesTheLever) {
  LampTrackInputs in = base_inputs({1, 2});
  in.lever.form = ResolvedLeverArm::Form::body_frd;
  in.lever.body_frd_m = Eigen::Vector3d(0.1, 0, 0.25);
  in.attitude = constant_attitude(0, 0, 90);
  const LampTrackResult r = compute_lamp_track(in);
  const UtcTime t0 = utc_from_civil(2018, 10, 9, 12, 30, 0, 0),
                t1 = utc_from_civil(2018, 10, 9, 12, 40, 0, 0);
  std::size_t inside = 0;
  for (const PosEpoch& e : llh().epochs) inside += (e.utc >= t0 && e.utc <= t1);
  EXPECT_EQ(r.track.epochs.size(), inside);
  EXPECT_EQ(r.report.dropped_no_attitude, 1878u - inside);
  ASSERT_FALSE(r.report.warnings.empty());
  // Yaw 90°: forward 0.1 m goes east; 0.25 m down.
  const LocalEnu site(kOrigin);
  for (const LampEpoch& e : r.track.epochs) {
    if (e.utc != utc_from_civil(2018, 10, 9, 12, 35, 0, 0)) continue;
    for (const PosEpoch& p : llh().epochs)
      if (p.utc == e.utc) {
        const Eigen::Vector3d a = to_site_enu(llh(), p, site).enu;
        EXPECT_LT((e.enu - a - Eigen::Vector3d(0.1, 0, -0.25)).norm(), 1e-12);
      }
  }
  in.attitude.reset();
  try {
    compute_lamp_track(in);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_EQ(e.field(), "lever_arm.body_frd_m");
  }
}

TEST(GnssStage, WarnsWhenTiltMakesTheVerticalFormWrongByMoreThan5mm) {
  LampTrackInputs in = base_inputs({1, 2});
  in.attitude = constant_attitude(10, 0, 0);  // 0.25·2·sin 5° = 43.6 mm
  LampTrackResult r = compute_lamp_track(in);
  EXPECT_NEAR(r.report.vertical_form_max_error_m, 0.0436, 1e-4);
  EXPECT_GT(r.report.vertical_form_epochs_over_5mm, 0u);
  ASSERT_EQ(r.report.warnings.size(), 1u);
  EXPECT_NE(r.report.warnings[0].find("vertical lever-arm form"), std::string::npos);
  EXPECT_EQ(r.track.epochs.size(), 1878u);     // the vertical form does not need attitude: nothing dropped
  in.attitude = constant_attitude(1, 0.5, 0);  // 0.25·tilt(1.118°) = 4.9 mm
  r = compute_lamp_track(in);
  EXPECT_LT(r.report.vertical_form_max_error_m, 0.005);
  EXPECT_TRUE(r.report.warnings.empty());
}

TEST(GnssStage, NothingLeftIsAnInputError) {
  LampTrackInputs in = base_inputs({1}, 0.001);
  try {
    compute_lamp_track(in);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_NE(std::string(e.what()).find("444"), std::string::npos);  // says what was read/dropped
  }
}

TEST(LampTrackCsv, RoundTripKeepsNanosecondsAndTenthMm) {
  LampTrack t;
  t.epochs.push_back(
      {UtcTime{1539087713LL * kNsPerSecond + 123456789}, {1.23456, -2.5, 3.00004}, {0.01, 0.02, 0.03}, 1});
  t.epochs.push_back({UtcTime{1539087714LL * kNsPerSecond + 1}, {-1000.00005, 0, 1e-5}, {0, 0, 0}, 2});
  const std::string text = format_lamp_track_csv(t);
  EXPECT_EQ(text.substr(0, text.find('\n')), "utc,E,N,U,sdE,sdN,sdU,quality,rEN,rEU,rNU");
  EXPECT_NE(text.find("2018-10-09T12:21:53.123456789Z,1.2346,-2.5000,3.0000,0.0100,0.0200,0.0300,1,,,\n"),
            std::string::npos);
  const LampTrack back = parse_lamp_track_csv(text, "t.csv");
  ASSERT_EQ(back.epochs.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(back.epochs[i].utc, t.epochs[i].utc);
    EXPECT_LE((back.epochs[i].enu - t.epochs[i].enu).cwiseAbs().maxCoeff(), 0.5e-4 + 1e-12);
    EXPECT_EQ(back.epochs[i].quality, t.epochs[i].quality);
    EXPECT_TRUE(std::isnan(back.epochs[i].vel_enu[0]));
  }
}

TEST(LampTrackCsv, RoundTripKeepsTheFullCovariance) {
  LampTrack t;
  LampEpoch e;
  e.utc = UtcTime{1539087713LL * kNsPerSecond};
  e.sd_enu = {0.008, 0.006, 0.012};
  const Eigen::Vector3d rho(0.3, -0.45, 0.2);
  Eigen::Matrix3d R;
  R << 1, rho[0], rho[1], rho[0], 1, rho[2], rho[1], rho[2], 1;
  e.cov_enu = e.sd_enu.asDiagonal() * R * e.sd_enu.asDiagonal();
  e.quality = 1;
  t.epochs.push_back(e);
  const std::string text = format_lamp_track_csv(t);
  EXPECT_NE(text.find(",1,0.3000,-0.4500,0.2000\n"), std::string::npos) << text;
  const LampTrack back = parse_lamp_track_csv(text, "t.csv");
  EXPECT_LE((back.epochs[0].cov_enu - e.cov_enu).cwiseAbs().maxCoeff(), 1e-12);
  // Without the correlation columns (an older file): not known.
  const LampTrack old = parse_lamp_track_csv(
      "utc,E,N,U,sdE,sdN,sdU,quality\n2018-10-09T12:21:53.000000000Z,1,2,3,0.01,0.01,0.02,1\n", "t.csv");
  EXPECT_TRUE(std::isnan(old.epochs[0].cov_enu(0, 1)));
}

void expect_bad_track(const std::string& body, long line, const std::string& field) {
  try {
    parse_lamp_track_csv("utc,E,N,U,sdE,sdN,sdU,quality\n" + body, "t.csv");
    ADD_FAILURE() << body;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
  }
}

TEST(LampTrackCsv, BadInput) {
  const std::string ok = "2018-10-09T12:21:53.000000000Z,1,2,3,0.01,0.01,0.02,1\n";
  expect_bad_track(ok + "2018-10-09T12:21:53.000000000Z,1,2,3,0.01,0.01,0.02,1\n", 3, "utc");
  expect_bad_track(ok + "2018-10-09T12:21:54.000000000Z,1,x,3,0.01,0.01,0.02,1\n", 3, "N");
  expect_bad_track(ok + "2018-10-09T12:21:54.000000000Z,1,2,3,0.01,-0.01,0.02,1\n", 3, "sdN");
  expect_bad_track(ok + "2018-10-09T12:21:54.000000000Z,1,2,3,0.01,0.01,0.02,9\n", 3, "quality");
  expect_bad_track("", 1, "utc");
  // Correlations: each in [−1, 1], and together those of some covariance.
  const auto bad_rho = [](const std::string& rho, const std::string& field) {
    try {
      parse_lamp_track_csv(
          "utc,E,N,U,sdE,sdN,sdU,quality,rEN,rEU,rNU\n"
          "2018-10-09T12:21:53.000000000Z,1,2,3,0.01,0.01,0.02,1," +
              rho + "\n",
          "t.csv");
      ADD_FAILURE() << rho;
    } catch (const Error& e) {
      EXPECT_EQ(e.line(), 2) << e.what();
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  bad_rho("1.2,0,0", "rEN");
  bad_rho("0,-1.5,0", "rEU");
  bad_rho("0.9,0.9,-0.9", "rEN");  // det R < 0
  bad_rho("0.1,,0.2", "rEU");
}

TEST(GnssStage, RunWritesTheTrackAndItsCounts) {
  const auto dir = test::scratch_dir("gnss_stage_run");
  test::write_text(dir / "lever.csv",
                   "session,target,E,N,U\n1,antenna,0,0,1.250\n1,lamp,0,0,1.000\n2,antenna,0,0,2.254\n"
                   "2,lamp,0,0,2.000\n");
  MissionConfig cfg;
  cfg.config_path = (dir / "mission.json").string();
  cfg.config_dir = dir.string();
  cfg.origin = kOrigin;
  cfg.gnss.pos_files = {pos_path("rover20181009_kin_llh_gpst.pos")};
  cfg.gnss.accept_quality = {1};
  cfg.gnss.max_sd_m = 0.05;
  cfg.gnss.max_gap_s = 1.5;
  cfg.lever_arm.kind = LeverArmConfig::Kind::total_station;
  cfg.lever_arm.total_station_file = (dir / "lever.csv").string();
  cfg.output_dir = (dir / "out").string();
  const StageLog log = run_gnss_stage(cfg);
  EXPECT_EQ(log.stage, "gnss");
  EXPECT_EQ(log.counts["epochs_read"], 1878);
  EXPECT_EQ(log.counts["dropped_quality"], 1434);
  EXPECT_EQ(log.counts["lever_arm"]["source"], "total_station");
  EXPECT_NEAR(log.counts["lever_arm"]["vertical_m"].get<double>(), 0.252, 1e-12);
  EXPECT_NEAR(log.counts["lever_arm"]["vertical_sd_m"].get<double>(), 0.002 * std::sqrt(2.0), 1e-12);
  const LampTrack t = read_lamp_track_csv(lamp_track_path(cfg));
  EXPECT_EQ(static_cast<long>(t.epochs.size()), log.counts["epochs_kept"].get<long>());
  // Compare with the pure computation.
  LampTrackInputs in = base_inputs({1}, 0.05, 1.5);
  in.lever.vertical_m = 0.252;
  in.lever.vertical_sd_m = 0.002 * std::sqrt(2.0);  // two sessions of 2 mm, as the stage resolved
  const LampTrackResult r = compute_lamp_track(in);
  ASSERT_EQ(t.epochs.size(), r.track.epochs.size());
  double max_rho = 0;
  for (std::size_t i = 0; i < t.epochs.size(); ++i) {
    ASSERT_EQ(t.epochs[i].utc, r.track.epochs[i].utc);
    ASSERT_LE((t.epochs[i].enu - r.track.epochs[i].enu).cwiseAbs().maxCoeff(), 0.5e-4 + 1e-9);
    // The full covariance survives the file to the sd's 0.05 mm and the correlations' 5e-5 rounding.
    const Eigen::Matrix3d& a = t.epochs[i].cov_enu;
    const Eigen::Matrix3d& b = r.track.epochs[i].cov_enu;
    ASSERT_TRUE(a.allFinite());
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        const double sj = std::sqrt(b(j, j)), sk = std::sqrt(b(k, k));
        ASSERT_LE(std::abs(a(j, k) - b(j, k)), 0.5e-4 * (sj + sk) + 2.5e-9 + 0.5e-4 * sj * sk) << i;
      }
    max_rho = std::max(max_rho, std::abs(b(0, 1)) / std::sqrt(b(0, 0) * b(1, 1)));
  }
  EXPECT_GT(max_rho, 0.05);  // the real .pos has sdne/sdeu/sdun: correlations to carry
  // A bad .pos path is an input error naming it.
  cfg.gnss.pos_files = {(dir / "missing.pos").string()};
  try {
    run_gnss_stage(cfg);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.exit_code(), 3);
    EXPECT_EQ(e.file(), (dir / "missing.pos").string());
  }
}

TEST(GnssStage, AttitudeNotOverlappingTheEpochsIsAnInputErrorNamingBothSpans) {
  // The real PX4 log flew on 2021-04-21; the real PPK data is of 2018-10-09.
  const std::string ulg = test::external("px4-ulog/sample_log_small.ulg").string();
  for (auto form : {ResolvedLeverArm::Form::vertical, ResolvedLeverArm::Form::body_frd}) {
    LampTrackInputs in = base_inputs({1, 2});
    in.lever.form = form;
    in.attitude = read_attitude_file(ulg);
    try {
      compute_lamp_track(in);
      FAIL() << "no overlap accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::input);
      EXPECT_EQ(e.exit_code(), 3);
      EXPECT_EQ(e.file(), ulg);
      const std::string m = e.what();
      // The log's span on UTC with PX4's default receiver lag of 110 ms (docs/gnss.md "Receiver lag").
      EXPECT_NE(m.find("2021-04-21T06:30:58.577Z … 2021-04-21T06:31:05.073Z"), std::string::npos) << m;
      EXPECT_NE(m.find("2018-10-09T12:21:53.000Z … 2018-10-09T12:54:26.000Z"), std::string::npos) << m;
      EXPECT_NE(m.find(pos_path("rover20181009_kin_llh_gpst.pos")), std::string::npos) << m;
      EXPECT_NE(m.find("does not overlap"), std::string::npos) << m;
    }
  }
  // Touching spans overlap: an attitude ending exactly on the first epoch is accepted.
  LampTrackInputs in = base_inputs({1, 2});
  AttitudeSeries a;
  a.path = "att.csv";
  const UtcTime first = utc_from_civil(2018, 10, 9, 12, 21, 53, 0);
  a.samples = {{UtcTime{first.ns - kNsPerSecond}, {}, 2}, {first, {}, 3}};
  in.attitude = a;
  EXPECT_NO_THROW(compute_lamp_track(in));
}

// A DataFlash log (built from the format's layout: no real one exists) over 12:30–12:40 UTC.
std::string dataflash_over_the_real_flight() {
  test::DataflashWriter w;
  w.define_att_and_gps();
  // 2018-10-09T12:30:00 UTC = GPS week 2022, 217,818 s (2 days + 12:30:18 GPST); boot 100 s then.
  const std::uint64_t boot0 = 100'000'000;
  for (int i = 0; i <= 3000; ++i) {
    const std::uint64_t t = boot0 + 200'000ULL * static_cast<std::uint64_t>(i);
    w.gps(t, 6, 2022, static_cast<std::uint32_t>(217'818'000 + (t - boot0) / 1000));
  }
  for (int i = 0; i <= 6000; ++i) w.att(boot0 + 100'000ULL * static_cast<std::uint64_t>(i), 0, 0, 90);
  return w.bytes();
}

// The real PPK flight with the built DataFlash log of dataflash_over_the_real_flight in `dir` as its
// attitude, and a body-frame lever arm.
MissionConfig autopilot_mission(const std::filesystem::path& dir) {
  test::write_text(dir / "flight.bin", dataflash_over_the_real_flight());
  MissionConfig cfg;
  cfg.config_path = (dir / "mission.json").string();
  cfg.config_dir = dir.string();
  cfg.origin = kOrigin;
  cfg.gnss.pos_files = {pos_path("rover20181009_kin_llh_gpst.pos")};
  cfg.gnss.accept_quality = {1, 2};
  cfg.gnss.max_sd_m = 1e9;
  cfg.gnss.max_gap_s = 1.5;
  cfg.lever_arm.kind = LeverArmConfig::Kind::body_frd;
  cfg.lever_arm.body_frd_m = Eigen::Vector3d(0.1, 0, 0.25);
  cfg.attitude_file = (dir / "flight.bin").string();
  cfg.output_dir = (dir / "out").string();
  return cfg;
}

TEST(GnssStage, RunReadsAnAutopilotLogAndReportsItsTimeFit) {
  const auto dir = test::scratch_dir("gnss_stage_autopilot");
  MissionConfig cfg = autopilot_mission(dir);
  cfg.attitude_gnss_lag_ms = 0;  // the built log's GPS stamps are the fixes' own instants
  const StageLog log = run_gnss_stage(cfg);
  const nlohmann::json& a = log.counts.at("attitude");
  EXPECT_EQ(a.at("format"), "ardupilot_dataflash");
  EXPECT_EQ(a.at("path"), cfg.attitude_file);
  EXPECT_EQ(a.at("samples"), 6001);
  EXPECT_EQ(a.at("utc_start"), "2018-10-09T12:30:00.000000000Z");
  EXPECT_EQ(a.at("utc_end"), "2018-10-09T12:40:00.000000000Z");
  EXPECT_EQ(a.at("gps_messages"), 3001);
  EXPECT_EQ(a.at("gps_used"), 3001);
  EXPECT_EQ(a.at("gps_rejected"), 0);
  EXPECT_EQ(a.at("gps_skipped"), 0);
  EXPECT_EQ(a.at("drift_fitted"), true);  // 600 s of GPS
  EXPECT_EQ(a.at("drift_ppm"), 0.0);
  EXPECT_EQ(a.at("residual_rms_us"), 0.0);
  EXPECT_EQ(a.at("boot_zero_utc"), "2018-10-09T12:28:20.000000000Z");
  EXPECT_EQ(a.at("truncated_bytes"), 0);
  EXPECT_EQ(a.at("gnss_lag_ms"), 0.0);
  EXPECT_EQ(a.at("gnss_lag_source"), "attitude.gnss_lag_ms");
  // The same track as the body-frame lever arm on the epochs inside 12:30–12:40 (yaw 90°).
  LampTrackInputs in = base_inputs({1, 2});
  in.lever.form = ResolvedLeverArm::Form::body_frd;
  in.lever.body_frd_m = Eigen::Vector3d(0.1, 0, 0.25);
  in.attitude = constant_attitude(0, 0, 90);
  EXPECT_EQ(log.counts.at("epochs_kept"), compute_lamp_track(in).track.epochs.size());

  // A CSV attitude reports its format and span only. Its samples are 1 s apart (the interpolation's
  // largest gap), so that the body-frame lever arm keeps the epochs they cover: a track needs two
  // (kMinLampTrackEpochs).
  test::write_text(
      dir / "att.csv",
      "utc,roll_deg,pitch_deg,yaw_deg\n2018-10-09T12:30:00Z,0,0,90\n2018-10-09T12:30:01Z,0,0,90\n"
      "2018-10-09T12:30:02Z,0,0,90\n");
  cfg.attitude_file = (dir / "att.csv").string();
  cfg.attitude_gnss_lag_ms.reset();
  const nlohmann::json c = run_gnss_stage(cfg).counts.at("attitude");
  EXPECT_EQ(c.at("format"), "csv");
  EXPECT_EQ(c.at("samples"), 3);
  EXPECT_FALSE(c.contains("gps_used"));
  // ... and takes no receiver lag: its times are UTC already.
  cfg.attitude_gnss_lag_ms = 120;
  try {
    run_gnss_stage(cfg);
    ADD_FAILURE() << "a receiver lag for a CSV attitude was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::usage);
    EXPECT_EQ(e.file(), cfg.config_path);
    EXPECT_EQ(e.field(), "attitude.gnss_lag_ms");
  }
}

// Without attitude.gnss_lag_ms a DataFlash log takes ArduPilot's 120 ms (autopilot_attitude_report.hpp):
// every GPS stamp moves back by it, so the whole attitude lands 120 ms later on UTC than with no lag.
TEST(GnssStage, AutopilotLogTakesItsTypesDefaultReceiverLag) {
  const auto dir = test::scratch_dir("gnss_stage_autopilot_lag");
  MissionConfig cfg = autopilot_mission(dir);
  const nlohmann::json a = run_gnss_stage(cfg).counts.at("attitude");
  EXPECT_EQ(a.at("gnss_lag_ms"), 120.0);
  EXPECT_EQ(a.at("gnss_lag_source"), "default for ardupilot_dataflash");
  EXPECT_EQ(a.at("utc_start"), "2018-10-09T12:30:00.120000000Z");
  EXPECT_EQ(a.at("utc_end"), "2018-10-09T12:40:00.120000000Z");
  EXPECT_EQ(a.at("boot_zero_utc"), "2018-10-09T12:28:20.120000000Z");
  EXPECT_EQ(a.at("residual_rms_us"), 0.0);  // a constant lag leaves the pairs' agreement as it was
  cfg.attitude_gnss_lag_ms = 220;           // an older u-blox: the same log, 100 ms later again
  EXPECT_EQ(run_gnss_stage(cfg).counts.at("attitude").at("utc_start"), "2018-10-09T12:30:00.220000000Z");
}

}  // namespace
}  // namespace rangecal

namespace rangecal {
namespace {

// What run.json's attitude counts say of a truncated log and of rejected GPS pairs is a warning
// too, each once, so that the console shows it (pipeline/cli/stage_summary.hpp prints warnings).
TEST(GnssStage, TruncatedLogAndRejectedGpsPairsAreWarnedOnce) {
  const auto dir = test::scratch_dir("gnss_stage_autopilot_damaged");
  MissionConfig cfg = autopilot_mission(dir);
  cfg.attitude_gnss_lag_ms = 0;
  test::DataflashWriter w;
  w.define_att_and_gps();
  const std::uint64_t boot0 = 100'000'000;
  for (int i = 0; i <= 3000; ++i) {
    const std::uint64_t t = boot0 + 200'000ULL * static_cast<std::uint64_t>(i);
    // One fix 2 s off the others' line: a jump the fit rejects.
    const std::uint32_t jump = i == 1500 ? 2000 : 0;
    w.gps(t, 6, 2022, static_cast<std::uint32_t>(217'818'000 + (t - boot0) / 1000) + jump);
  }
  for (int i = 0; i <= 6000; ++i) w.att(boot0 + 100'000ULL * static_cast<std::uint64_t>(i), 0, 0, 90);
  const std::string bytes = w.bytes();
  test::write_text(dir / "flight.bin", bytes.substr(0, bytes.size() - 5));  // cut inside the last ATT
  const StageLog log = run_gnss_stage(cfg);
  const nlohmann::json& a = log.counts.at("attitude");
  ASSERT_GT(a.at("truncated_bytes").get<int>(), 0);
  ASSERT_EQ(a.at("gps_rejected"), 1);
  int truncated = 0, rejected = 0;
  for (const std::string& w : log.warnings) {
    if (w.find("the log is truncated") != std::string::npos) {
      ++truncated;
      EXPECT_NE(w.find(cfg.attitude_file), std::string::npos) << w;
      EXPECT_NE(w.find(std::to_string(a.at("truncated_bytes").get<int>()) + " byte(s)"), std::string::npos)
          << w;
    }
    if (w.find("time pairs rejected") != std::string::npos) {
      ++rejected;
      EXPECT_NE(w.find("1 of 3001 GPS"), std::string::npos) << w;
    }
  }
  EXPECT_EQ(truncated, 1);
  EXPECT_EQ(rejected, 1);
  // A whole log with no jump says neither.
  cfg = autopilot_mission(dir);
  cfg.attitude_gnss_lag_ms = 0;
  for (const std::string& w : run_gnss_stage(cfg).warnings) {
    EXPECT_EQ(w.find("truncated"), std::string::npos) << w;
    EXPECT_EQ(w.find("rejected"), std::string::npos) << w;
  }
}

}  // namespace
}  // namespace rangecal
