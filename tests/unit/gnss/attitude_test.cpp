// Attitude CSV, interpolation (yaw across ±180°) and R_nb against seed 002 eq. 4 written out.
#include "gnss/track/attitude.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <random>

#include "config/error.hpp"
#include "gnss/formats/attitude_csv.hpp"
#include "support/paths.hpp"

namespace rangecal {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

AttitudeSeries series(const std::string& body) {
  return parse_attitude_csv("utc,roll_deg,pitch_deg,yaw_deg\n" + body, "att.csv");
}

UtcTime at(const char* iso) {
  return *parse_iso8601_utc(iso);
}

TEST(Attitude, LinearRollPitchAndNanosecondTimes) {
  const auto s = series(
      "2018-10-09T12:00:00.000000001Z,0,0,10\n"
      "2018-10-09T12:00:00.100000001Z,2,-4,20\n");
  ASSERT_EQ(s.samples.size(), 2u);
  EXPECT_EQ(s.samples[0].utc.ns % kNsPerSecond, 1);
  const auto a = interpolate_attitude(s, at("2018-10-09T12:00:00.025000001Z"), 1.0);
  ASSERT_TRUE(a);
  EXPECT_NEAR(a->roll_deg, 0.5, 1e-12);
  EXPECT_NEAR(a->pitch_deg, -1.0, 1e-12);
  EXPECT_NEAR(a->yaw_deg, 12.5, 1e-12);
  // Exactly on the samples.
  EXPECT_NEAR(interpolate_attitude(s, s.samples[0].utc, 1.0)->yaw_deg, 10, 1e-12);
  EXPECT_NEAR(interpolate_attitude(s, s.samples[1].utc, 1.0)->yaw_deg, 20, 1e-12);
}

TEST(Attitude, YawInterpolatesAcrossPlusMinus180) {
  const auto s = series(
      "2018-10-09T12:00:00Z,0,0,170\n"
      "2018-10-09T12:00:01Z,0,0,-170\n"
      "2018-10-09T12:00:02Z,0,0,170\n"
      "2018-10-09T12:00:03Z,0,0,350\n"
      "2018-10-09T12:00:04Z,0,0,10\n");
  EXPECT_NEAR(std::abs(interpolate_attitude(s, at("2018-10-09T12:00:00.5Z"), 2)->yaw_deg), 180, 1e-9);
  EXPECT_NEAR(interpolate_attitude(s, at("2018-10-09T12:00:00.25Z"), 2)->yaw_deg, 175, 1e-9);
  EXPECT_NEAR(interpolate_attitude(s, at("2018-10-09T12:00:00.75Z"), 2)->yaw_deg, -175, 1e-9);
  EXPECT_NEAR(interpolate_attitude(s, at("2018-10-09T12:00:01.25Z"), 2)->yaw_deg, -175, 1e-9);
  // 350° (= −10°) → 10° passes through 0°, not through 180°.
  EXPECT_NEAR(interpolate_attitude(s, at("2018-10-09T12:00:03.5Z"), 2)->yaw_deg, 0, 1e-9);
  EXPECT_NEAR(interpolate_attitude(s, at("2018-10-09T12:00:03.25Z"), 2)->yaw_deg, -5, 1e-9);
}

TEST(Attitude, OutsideCoverageOrAcrossAHoleIsNotInterpolated) {
  const auto s = series(
      "2018-10-09T12:00:00Z,0,0,0\n"
      "2018-10-09T12:00:01Z,0,0,0\n"
      "2018-10-09T12:00:05Z,0,0,0\n");
  EXPECT_FALSE(interpolate_attitude(s, at("2018-10-09T11:59:59.999999999Z"), 1.5));
  EXPECT_FALSE(interpolate_attitude(s, at("2018-10-09T12:00:05.000000001Z"), 1.5));
  EXPECT_TRUE(interpolate_attitude(s, at("2018-10-09T12:00:00.5Z"), 1.5));
  EXPECT_FALSE(interpolate_attitude(s, at("2018-10-09T12:00:03Z"), 1.5));  // 4 s hole > 1.5 s
  EXPECT_TRUE(interpolate_attitude(s, at("2018-10-09T12:00:03Z"), 5.0));
}

TEST(Attitude, RotationIsSeed002Eq4WithAnglesPutRight) {
  // seed 002 eq. 4 literally, with φ = yaw, θ = pitch, ψ = roll (seeds/NOTES.md).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 200; ++i) {
    const Attitude a{u(rng) * 180, u(rng) * 90, u(rng) * 180};
    const double f = a.yaw_deg * kDeg, t = a.pitch_deg * kDeg, p = a.roll_deg * kDeg;
    const Eigen::Vector3d d(u(rng), u(rng), u(rng));
    using std::cos;
    using std::sin;
    const Eigen::Vector3d eq4(d.x() * cos(f) * cos(t) + d.y() * (cos(f) * sin(p) * sin(t) - cos(p) * sin(f)) +
                                  d.z() * (cos(p) * cos(f) * sin(t) + sin(p) * sin(f)),
                              d.x() * cos(t) * sin(f) + d.y() * (sin(p) * sin(f) * sin(t) + cos(p) * cos(f)) +
                                  d.z() * (cos(p) * sin(f) * sin(t) - cos(f) * sin(p)),
                              -d.x() * sin(t) + d.y() * cos(t) * sin(p) + d.z() * cos(p) * cos(t));
    const Eigen::Matrix3d R = rotation_nb(a);
    EXPECT_LT((R * d - eq4).norm(), 1e-12);
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
  }
}

TEST(Attitude, FromQuaternionInvertsRotationNb) {
  // A quaternion built by Eigen from R_nb of known angles must give those angles back.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 500; ++i) {
    const Attitude a{u(rng) * 180, u(rng) * 89, u(rng) * 180};
    const Eigen::Quaterniond q(rotation_nb(a));
    for (double scale : {1.0, 1.0 + 1e-4}) {  // not exactly unit, as a logged float quaternion
      const Attitude b = attitude_from_quaternion(scale * q.w(), scale * q.x(), scale * q.y(), scale * q.z());
      EXPECT_NEAR(b.roll_deg, a.roll_deg, 1e-9);
      EXPECT_NEAR(b.pitch_deg, a.pitch_deg, 1e-9);
      EXPECT_NEAR(b.yaw_deg, a.yaw_deg, 1e-9);
    }
    // −q is the same rotation.
    const Attitude c = attitude_from_quaternion(-q.w(), -q.x(), -q.y(), -q.z());
    EXPECT_NEAR(c.yaw_deg, a.yaw_deg, 1e-9);
  }
  // Yaw 180° about NED z: q = [0, 0, 0, 1]; the result is +180, never −180.
  EXPECT_EQ(attitude_from_quaternion(0, 0, 0, 1).yaw_deg, 180);
  EXPECT_EQ(attitude_from_quaternion(0, 0, 0, -1).yaw_deg, 180);
  // Roll +90° (right wing down): q = [cos 45°, sin 45°, 0, 0].
  EXPECT_NEAR(attitude_from_quaternion(std::sqrt(0.5), std::sqrt(0.5), 0, 0).roll_deg, 90, 1e-12);
  const Attitude zero = attitude_from_quaternion(0, 0, 0, 0);
  EXPECT_EQ(zero.roll_deg, 0);
  EXPECT_EQ(zero.yaw_deg, 0);
}

TEST(Attitude, WrapDeg) {
  EXPECT_DOUBLE_EQ(wrap_deg_180(180), 180);
  EXPECT_DOUBLE_EQ(wrap_deg_180(-180), 180);
  EXPECT_DOUBLE_EQ(wrap_deg_180(190), -170);
  EXPECT_DOUBLE_EQ(wrap_deg_180(-190), 170);
  EXPECT_DOUBLE_EQ(wrap_deg_180(720 + 5), 5);
}

void expect_bad(const std::string& body, long line, const std::string& field) {
  try {
    series(body);
    ADD_FAILURE() << "no error for " << body;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::input);
    EXPECT_EQ(e.file(), "att.csv");
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
  }
}

TEST(AttitudeBadInput, EachErrorNamesLineAndField) {
  expect_bad("2018-10-09T12:00:00Z,0,0,0\n2018-10-09T12:00:01,0,0,0\n", 3, "utc");   // no Z
  expect_bad("2018-10-09T12:00:00Z,0,0,0\n2018-10-09T12:00:00Z,0,0,0\n", 3, "utc");  // not increasing
  expect_bad("2018-10-09T12:00:00Z,0,0,0\n2018-10-09T12:00:01Z,abc,0,0\n", 3, "roll_deg");
  expect_bad("2018-10-09T12:00:00Z,0,95,0\n2018-10-09T12:00:01Z,0,0,0\n", 2, "pitch_deg");
  expect_bad("2018-10-09T12:00:00Z,0,0,0\n", 2, "utc");  // a single sample
  // Found by fuzzing (docs/reliability.md "Fuzzing"): a year whose time overflows int64 ns was
  // undefined behaviour; years outside 1970-2200 are an error naming the line and the field.
  expect_bad("2018-10-09T12:00:00Z,0,0,0\n6022-10-09T12:00:01Z,0,0,0\n", 3, "utc");
  expect_bad("1022-10-09T12:00:00Z,0,0,0\n2018-10-09T12:00:01Z,0,0,0\n", 2, "utc");
  try {
    series("2018-10-09T12:00:00Z,0,0,0\n6022-10-09T12:00:01Z,0,0,0\n");
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("att.csv:3"), std::string::npos) << what;
    EXPECT_NE(what.find("utc"), std::string::npos) << what;
    EXPECT_NE(what.find("1970-2200"), std::string::npos) << what;
  }
  try {
    read_attitude_csv("/nonexistent/att.csv");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.file(), "/nonexistent/att.csv");
  }
}

}  // namespace
}  // namespace rangecal
