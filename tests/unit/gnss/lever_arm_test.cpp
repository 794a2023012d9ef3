// Lever arm: hand-checked cases, the vertical form, a randomized round trip, total station.
#include "gnss/track/lever_arm.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "config/error.hpp"
#include "gnss/formats/ardupilot_dataflash.hpp"
#include "gnss/track/attitude.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
const Eigen::Vector3d kAntenna(12.0, -3.0, 40.0);

TEST(LeverArm, Yaw90TurnsAForwardLeverEast) {
  const Eigen::Vector3d lamp = lamp_enu_full(kAntenna, rotation_nb({0, 0, 90}), {1.0, 0, 0});
  EXPECT_LT((lamp - (kAntenna + Eigen::Vector3d(1, 0, 0))).norm(), 1e-12);
  // Yaw 0: forward is north.
  EXPECT_LT(
      (lamp_enu_full(kAntenna, rotation_nb({0, 0, 0}), {1.0, 0, 0}) - kAntenna - Eigen::Vector3d(0, 1, 0))
          .norm(),
      1e-12);
}

TEST(LeverArm, Roll90TurnsARightLeverDown) {
  const Eigen::Vector3d lamp = lamp_enu_full(kAntenna, rotation_nb({90, 0, 0}), {0, 1.0, 0});
  EXPECT_LT((lamp - (kAntenna + Eigen::Vector3d(0, 0, -1))).norm(), 1e-12);
}

TEST(LeverArm, Pitch90TurnsAForwardLeverUp) {
  const Eigen::Vector3d lamp = lamp_enu_full(kAntenna, rotation_nb({0, 90, 0}), {1.0, 0, 0});
  EXPECT_LT((lamp - (kAntenna + Eigen::Vector3d(0, 0, 1))).norm(), 1e-12);
}

TEST(LeverArm, VerticalFormEqualsFullFormAtZeroTilt) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> yaw(-180, 180), d(0.05, 0.6);
  for (int i = 0; i < 50; ++i) {
    const double v = d(rng);
    const Eigen::Matrix3d R = rotation_nb({0, 0, yaw(rng)});
    EXPECT_LT((lamp_enu_full(kAntenna, R, {0, 0, v}) - lamp_enu_vertical(kAntenna, v)).norm(), 1e-12);
    EXPECT_LT(vertical_form_error_m(R, v), 1e-12);
  }
  EXPECT_DOUBLE_EQ(lamp_enu_vertical(kAntenna, 0.25)[2], 39.75);
}

TEST(LeverArm, VerticalFormErrorGrowsWithTilt) {
  // |R·(0,0,d) − (0,0,d)| = d·2·sin(tilt/2); roll 10°, d = 0.25 m → 43.6 mm.
  const double err = vertical_form_error_m(rotation_nb({10, 0, 30}), 0.25);
  EXPECT_NEAR(err, 0.25 * 2 * std::sin(5 * kDeg), 1e-12);
  const Attitude a{7, -4, 123};
  const Eigen::Matrix3d R = rotation_nb(a);
  EXPECT_NEAR(vertical_form_error_m(R, 0.3),
              (lamp_enu_full(kAntenna, R, {0, 0, 0.3}) - lamp_enu_vertical(kAntenna, 0.3)).norm(), 1e-12);
}

TEST(LeverArm, RandomizedRoundTripAgainstAngleAxis) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 500; ++i) {
    const Attitude a{u(rng) * 180, u(rng) * 89, u(rng) * 180};
    const Eigen::Vector3d lever(u(rng), u(rng), u(rng));
    const Eigen::Vector3d ant(u(rng) * 1000, u(rng) * 1000, u(rng) * 100);
    const Eigen::Matrix3d R = rotation_nb(a);
    const Eigen::Vector3d lamp = lamp_enu_full(ant, R, lever);
    // Independent construction of R_nb from Eigen's axis-angle rotations.
    const Eigen::Matrix3d Re = (Eigen::AngleAxisd(a.yaw_deg * kDeg, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(a.pitch_deg * kDeg, Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(a.roll_deg * kDeg, Eigen::Vector3d::UnitX()))
                                   .toRotationMatrix();
    EXPECT_LT((R - Re).norm(), 1e-12);
    // Back: lever = R_nbᵀ · NED(lamp − antenna); the distance is the lever's length.
    EXPECT_LT((R.transpose() * enu_to_ned(lamp - ant) - lever).norm(), 1e-9);
    EXPECT_NEAR((lamp - ant).norm(), lever.norm(), 1e-9);
  }
}

TEST(TotalStation, MeanAndSampleSdOverSessions) {
  const TotalStationOffset t = parse_total_station_csv(
      "session,target,E,N,U\n"
      "s1,antenna,1.0,2.0,10.300\n"
      "s1,lamp,1.0,2.0,10.050\n"
      "s2,lamp,5.0,6.0,20.000\n"
      "s2,antenna,5.0,6.0,20.252\n"
      "s3,antenna,0,0,-1.000\n"
      "s3,lamp,0,0,-1.248\n",
      "lever.csv");
  ASSERT_EQ(t.sessions.size(), 3u);
  EXPECT_EQ(t.sessions[1], "s2");
  EXPECT_NEAR(t.per_session_m[0], 0.250, 1e-12);
  EXPECT_NEAR(t.per_session_m[1], 0.252, 1e-12);
  EXPECT_NEAR(t.per_session_m[2], 0.248, 1e-12);
  EXPECT_NEAR(t.vertical_m, 0.250, 1e-12);
  EXPECT_NEAR(t.sd_m, 0.002, 1e-12);  // sqrt((0 + 0.002² + 0.002²) / 2)
}

void expect_bad(const std::string& body, long line, const std::string& field) {
  try {
    parse_total_station_csv("session,target,E,N,U\n" + body, "lever.csv");
    ADD_FAILURE() << "no error for " << body;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "lever.csv");
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
  }
}

TEST(TotalStation, BadInput) {
  expect_bad("s1,antenna,0,0,1\ns1,lens,0,0,0\n", 3, "target");
  expect_bad("s1,antenna,0,0,1\ns1,antenna,0,0,0\n", 3, "target");
  expect_bad("s1,antenna,0,0,1\ns1,lamp,0,0,0\ns2,antenna,0,0,1\n", 4, "target");
  expect_bad("s1,antenna,0,0,1\ns1,lamp,0,0,x\n", 3, "U");
  expect_bad("", 1, "session");
  // Physical ranges: the lamp hangs within 10 m of the antenna; coordinates are site-sized.
  expect_bad("s1,antenna,0,0,100\ns1,lamp,0,0,50\n", 3, "U");
  expect_bad("s1,lamp,0,0,1.2\ns1,antenna,0,0,-9\n", 2, "U");
  expect_bad("s1,antenna,1e9,0,1\ns1,lamp,0,0,0\n", 2, "E");
  EXPECT_NO_THROW(
      parse_total_station_csv("session,target,E,N,U\r\ns1,antenna,0,0,10.5\r\ns1,lamp,0,0,0.6\r\n", "l.csv"));
}

// A yaw rate ω turns a lever of horizontal length ℓ at ω·ℓ (m/s); the vertical part does not move.
TEST(LeverMotion, ConstantYawRateTurnsTheHorizontalLeverAtOmegaTimesItsLength) {
  AttitudeSeries s;
  const UtcTime t0 = utc_from_civil(2026, 5, 1, 12, 0, 0, 0);
  for (int i = 0; i <= 100; ++i)  // 10 Hz, 30°/s of yaw
    s.samples.push_back({UtcTime{t0.ns + i * 100'000'000LL}, {0, 0, -150.0 + 3.0 * i}});
  const double omega = 30.0 * 3.14159265358979323846 / 180.0;
  const auto rate =
      lever_motion_mps(s, UtcTime{t0.ns + 5'030'000'000LL}, Eigen::Vector3d(0.3, 0.4, 0.25), 1.0);
  ASSERT_TRUE(rate.has_value());
  // Yaw is interpolated linearly: the ±20 ms chord of a 30°/s turn is ω·ℓ·sinc(ω·20 ms) ≈ ω·ℓ·(1 − 5e-5).
  EXPECT_NEAR(*rate, omega * 0.5, omega * 0.5 * 1e-4);
  EXPECT_FALSE(lever_motion_mps(s, UtcTime{t0.ns - 1}, Eigen::Vector3d(0.3, 0.4, 0.25), 1.0).has_value());
}

// The real ArduCopter log (tests/data/external/ardupilot-dataflash/SOURCE.md): a 0.33 m lever below
// the antenna moves by up to ~2 cm when its attitude is put 120 ms off on UTC (the receiver lag
// of docs/gnss.md) — computed here directly from the attitude at t and t + 120 ms — and the rate
// the gnss stage reports (lever_motion_mps × 120 ms) says the same to within the curvature of the
// motion over 120 ms.
TEST(LeverMotion, RealArduCopterLogMovesTheLampUpToAbout2cmPer120ms) {
  const AttitudeSeries s =
      read_dataflash_attitude(test::external("ardupilot-dataflash/spark404_log.bin").string());
  const Eigen::Vector3d lever(0, 0, 0.33);
  constexpr std::int64_t kLagNs = 120'000'000;
  double shift_max = 0, shift_ss = 0, rate_max = 0;
  int n = 0;
  for (std::int64_t t = s.samples.front().utc.ns + 50'000'000; t + kLagNs < s.samples.back().utc.ns;
       t += 10'000'000) {  // every 10 ms of the flight
    const auto a = interpolate_attitude(s, UtcTime{t}, 1.0);
    const auto b = interpolate_attitude(s, UtcTime{t + kLagNs}, 1.0);
    ASSERT_TRUE(a && b);
    const double d = (rotation_nb(*b) * lever - rotation_nb(*a) * lever).norm();
    shift_max = std::max(shift_max, d);
    shift_ss += d * d;
    ++n;
    if (const auto r = lever_motion_mps(s, UtcTime{t}, lever, 1.0)) rate_max = std::max(rate_max, *r);
  }
  const double shift_rms = std::sqrt(shift_ss / n);
  std::printf("  120 ms of attitude time: lamp moves up to %.1f mm (rms %.1f mm); rate × 120 ms = %.1f mm\n",
              shift_max * 1e3, shift_rms * 1e3, rate_max * 0.120 * 1e3);
  // Measured here: 20.5 mm (rms 3.5 mm) with the attitude interpolated every 10 ms; the issue that
  // asked for the lag measured 17.9 mm (rms 3.4 mm) on the same log by its own means.
  EXPECT_GT(shift_max * 1e3, 15.0);
  EXPECT_LT(shift_max * 1e3, 25.0);
  EXPECT_NEAR(shift_rms * 1e3, 3.4, 0.6);
  EXPECT_GT(rate_max * 0.120, 0.7 * shift_max);
  EXPECT_LT(rate_max * 0.120, 1.6 * shift_max);
}

std::string message_of(const std::string& body) {
  try {
    parse_total_station_csv("session,target,E,N,U\n" + body, "lever.csv");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// The whole 3-D separation of a session's marks is held to the 10 m of the lever arm, not only its
// height: a lamp mark 500 m away horizontally is another object's mark, whatever its U says.
TEST(TotalStation, ASessionWhoseMarksLieFarApartHorizontallyIsNamed) {
  const std::string ok = "s1,antenna,10,20,1.25\ns1,lamp,10,20,1.00\ns2,antenna,0,0,1.25\ns2,lamp,0,0,1.00\n";
  // Session s3's lamp mark 500 m east of its antenna mark: line 7 (the lamp row), field E.
  const std::string far = ok + "s3,antenna,0,0,1.25\ns3,lamp,500,0,1.00\n";
  expect_bad(far, 7, "E");
  EXPECT_NE(message_of(far).find("session 's3'"), std::string::npos) << message_of(far);
  EXPECT_NE(message_of(far).find("500.000 m from the antenna mark (E 500.000, N 0.000, U -0.250 m)"),
            std::string::npos)
      << message_of(far);
  // North and diagonal: the field is the axis that carries most of it; 7.1 m diagonal is within 10 m.
  expect_bad("s1,antenna,0,0,1.25\ns1,lamp,3,-12,1.00\n", 3, "N");
  EXPECT_NO_THROW(
      parse_total_station_csv("session,target,E,N,U\ns1,antenna,0,0,1\ns1,lamp,5,5,0.5\n", "l.csv"));
}

// Sessions measure one lever: a session further than 2 cm from the median of the others is named
// with its value; two sessions that disagree are both named, since which is wrong cannot be told.
TEST(TotalStation, ASessionThatDisagreesWithTheOthersIsNamed) {
  const std::string three =
      "a,antenna,0,0,1.250\na,lamp,0,0,1.000\n"    // 0.250
      "b,antenna,0,0,2.251\nb,lamp,0,0,2.000\n"    // 0.251
      "c,antenna,0,0,0.3305\nc,lamp,0,0,0.000\n";  // 0.3305: 8.0 cm off
  expect_bad(three, 7, "U");
  const std::string m = message_of(three);
  EXPECT_NE(m.find("session 'c' gives 0.3305 m"), std::string::npos) << m;
  EXPECT_NE(m.find("8.0 cm from the median of the other sessions (0.2505 m"), std::string::npos) << m;
  // The bad session first in the file, among four.
  const std::string four = "x,antenna,0,0,1.10\nx,lamp,0,0,1.00\n" +
                           std::string("a,antenna,0,0,1.250\na,lamp,0,0,1.000\n") +
                           "b,antenna,0,0,2.251\nb,lamp,0,0,2.000\nc,antenna,0,0,0.249\nc,lamp,0,0,0.000\n";
  expect_bad(four, 3, "U");
  EXPECT_NE(message_of(four).find("session 'x'"), std::string::npos) << message_of(four);
  const std::string two = "a,antenna,0,0,1.25\na,lamp,0,0,1.00\nb,antenna,0,0,1.30\nb,lamp,0,0,1.00\n";
  expect_bad(two, 5, "U");
  EXPECT_NE(message_of(two).find("sessions 'a' (0.2500 m) and 'b' (0.3000 m) disagree by 5.0 cm"),
            std::string::npos)
      << message_of(two);
  // Within 2 cm: accepted, and the sd says how well they agree (1.9 cm apart).
  const TotalStationOffset t = parse_total_station_csv(
      "session,target,E,N,U\na,antenna,0,0,1.250\na,lamp,0,0,1.000\nb,antenna,0,0,1.269\nb,lamp,0,0,1.000\n",
      "l.csv");
  EXPECT_NEAR(t.vertical_m, 0.2595, 1e-12);
}

}  // namespace
}  // namespace rangecal
