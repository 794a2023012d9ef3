// The report's verdict (pipeline/report/verdict.hpp) on each side of its thresholds: residual RMS
// 1.5x the noise model's, the check poles' mean ΔR against the bar, the weak-parameter effect from
// the flight volume's median σ (else the centre σ of 0.5 px), the datum floor ratio 1.25.
#include "pipeline/report/verdict.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace rangecal {
namespace {

CameraEvidence evidence(double rms_px, double expected_rms_px, double centre_sigma_px, bool weak) {
  CameraEvidence e;
  e.consistency.n = 100;
  e.consistency.rms_px = rms_px;
  e.consistency.expected_rms_px = expected_rms_px;
  e.centre_sigma_px = centre_sigma_px;
  e.weak_parameters = weak;
  return e;
}

SliceStats volume(double median_m) {
  SliceStats s;
  s.n = 40;
  s.min = median_m / 2, s.median = median_m, s.max = 2 * median_m;
  return s;
}

TEST(Verdict, ResidualsUpToOneAndAHalfTimesTheModelAreAsExpected) {
  const SliceStats none;
  const CameraVerdict at = judge_camera(evidence(0.15, 0.1, 0.2, false), none, 0.01);
  EXPECT_DOUBLE_EQ(at.residual_ratio, 1.5);
  EXPECT_EQ(at.reading, ResidualReading::as_expected);
  const CameraVerdict beyond = judge_camera(evidence(0.1501, 0.1, 0.2, false), none, 0.01);
  EXPECT_EQ(beyond.reading, ResidualReading::too_large);
  EXPECT_NEAR(beyond.residual_ratio, 1.501, 1e-12);
  const CameraVerdict nothing = judge_camera(evidence(std::nan(""), 0.1, 0.2, false), none, 0.01);
  EXPECT_EQ(nothing.reading, ResidualReading::no_residuals);
  EXPECT_EQ(nothing.weak, WeakParameterEffect::none);
}

TEST(Verdict, AClockOffsetIsNamedOnlyWhenTheResidualsShowOne) {
  const SliceStats none;
  CameraEvidence e = evidence(0.2, 0.1, 0.2, false);
  e.clock = {100, 0.0040, 0.0010};  // 4 σ
  const CameraVerdict shown = judge_camera(e, none, 0.01);
  EXPECT_EQ(shown.reading, ResidualReading::too_large);
  EXPECT_TRUE(shown.clock_offset_shown);
  EXPECT_DOUBLE_EQ(shown.clock_offset_s, 0.004);
  e.clock.sigma_s = 0.0014;  // 2.9 σ: the residuals do not show a clock offset
  EXPECT_FALSE(judge_camera(e, none, 0.01).clock_offset_shown);
  e.clock = {};  // no velocities in correspondences.csv: nothing to show
  EXPECT_FALSE(judge_camera(e, none, 0.01).clock_offset_shown);
  CameraEvidence fine = evidence(0.14, 0.1, 0.2, false);  // residuals as expected: no cause to look for
  fine.clock = {100, 0.0040, 0.0010};
  fine.correlated_ppk = true;
  const CameraVerdict v = judge_camera(fine, none, 0.01);
  EXPECT_EQ(v.reading, ResidualReading::as_expected);
  EXPECT_FALSE(v.clock_offset_shown);
  EXPECT_TRUE(v.correlated_ppk);
}

TEST(Verdict, WeakParametersAreJudgedByTheFlightVolumeAgainstTheBar) {
  // With a flight-volume prediction its median decides, whatever the centre σ.
  EXPECT_EQ(judge_camera(evidence(0.1, 0.1, 3.0, true), volume(0.010), 0.010).weak,
            WeakParameterEffect::harmless);
  EXPECT_EQ(judge_camera(evidence(0.1, 0.1, 0.01, true), volume(0.0101), 0.010).weak,
            WeakParameterEffect::matters);
  // Without one, the centre σ against 0.5 px.
  const SliceStats none;
  EXPECT_EQ(judge_camera(evidence(0.1, 0.1, 0.499, true), none, 0.010).weak, WeakParameterEffect::harmless);
  EXPECT_EQ(judge_camera(evidence(0.1, 0.1, 0.5, true), none, 0.010).weak, WeakParameterEffect::matters);
  // No covariance: no centre σ, nothing to judge by.
  EXPECT_EQ(judge_camera(evidence(0.1, 0.1, std::nan(""), true), volume(0.001), 0.010).weak,
            WeakParameterEffect::not_judgeable);
  // No such warning: nothing said.
  EXPECT_EQ(judge_camera(evidence(0.1, 0.1, 3.0, false), volume(0.5), 0.010).weak, WeakParameterEffect::none);
}

IntersectionRow pole(const char* id, double dR, double sigma_m) {
  IntersectionRow r;
  r.id = id;
  r.d_enu = Eigen::Vector3d(dR, 0, 0);
  r.dR = dR;
  r.sigma_m = sigma_m;
  return r;
}

TEST(Verdict, CheckPolesMeetTheBarWhenTheirMeanDeltaRDoesNotExceedIt) {
  EXPECT_FALSE(judge_check_poles(std::nullopt, 0.01));
  EXPECT_FALSE(judge_check_poles(std::vector<IntersectionRow>{}, 0.01));
  // Mean ΔR (2⁻⁷ + 1.5·2⁻⁷) / 2 = 1.25·2⁻⁷ m (≈ 9.77 mm, exact in binary): met at a bar of exactly
  // that, not at 9.7 mm.
  const double a = 0.0078125, b = 1.5 * a, mean = 1.25 * a;
  const std::vector<IntersectionRow> rows{pole("P1", a, 0.004), pole("P2", b, 0.006)};
  const auto at = judge_check_poles(rows, mean);
  ASSERT_TRUE(at);
  EXPECT_EQ(at->means.n, 2);
  EXPECT_EQ(at->means.mean_dR, mean);
  EXPECT_EQ(at->means.max_dR, b);
  EXPECT_TRUE(at->met);
  EXPECT_FALSE(judge_check_poles(rows, 0.0097)->met);
}

TEST(Verdict, TheDatumLimitsWithinOnePointTwoFiveOfItsFloor) {
  FlightVolumeSigma v;
  v.over_datum_floor = 1.25;
  EXPECT_TRUE(datum_limited(v));
  v.over_datum_floor = 1.2501;
  EXPECT_FALSE(datum_limited(v));
  v.over_datum_floor = std::nan("");  // no floor
  EXPECT_FALSE(datum_limited(v));
}

}  // namespace
}  // namespace rangecal
