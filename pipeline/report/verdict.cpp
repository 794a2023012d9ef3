#include "pipeline/report/verdict.hpp"

#include <cmath>

namespace rangecal {

CameraVerdict judge_camera(const CameraEvidence& e, const SliceStats& volume, double bar_mean_dR_m) {
  CameraVerdict v;
  v.residual_ratio = e.consistency.rms_px / e.consistency.expected_rms_px;
  if (!std::isfinite(v.residual_ratio))
    v.reading = ResidualReading::no_residuals;
  else if (v.residual_ratio <= kResidualRatioOk)
    v.reading = ResidualReading::as_expected;
  else
    v.reading = ResidualReading::too_large;
  v.correlated_ppk = e.correlated_ppk;
  v.clock_offset_s = e.clock.offset_s;
  v.clock_offset_shown = v.reading == ResidualReading::too_large && e.clock.n > 0 &&
                         std::abs(e.clock.offset_s) > kClockOffsetSignificance * e.clock.sigma_s;
  // A poorly determined or strongly correlated parameter matters only through where it moves the
  // flown points: the flight volume's intersection σ against the bar, else the centre σ.
  if (!e.weak_parameters)
    v.weak = WeakParameterEffect::none;
  else if (!std::isfinite(e.centre_sigma_px))
    v.weak = WeakParameterEffect::not_judgeable;
  else if (volume.n > 0 ? volume.median <= bar_mean_dR_m : e.centre_sigma_px < kHarmlessCentreSigmaPx)
    v.weak = WeakParameterEffect::harmless;
  else
    v.weak = WeakParameterEffect::matters;
  return v;
}

std::optional<CheckPoleVerdict> judge_check_poles(const std::optional<std::vector<IntersectionRow>>& rows,
                                                  double bar_mean_dR_m) {
  if (!rows || rows->empty()) return std::nullopt;
  CheckPoleVerdict v;
  v.means = intersection_means(*rows);
  v.met = v.means.mean_dR <= bar_mean_dR_m;
  return v;
}

bool datum_limited(const FlightVolumeSigma& v) {
  return v.over_datum_floor <= kDatumLimitedRatio;
}

}  // namespace rangecal
