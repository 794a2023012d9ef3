#pragma once
// The report's verdict (report.html "Verdict", docs/outputs.md), judged apart from its HTML: per
// camera whether its lamp residuals are what the noise model expects, whether the check poles meet
// the bar, and what a camera's poorly determined or correlated parameters mean for the
// intersection. The thresholds are here and nowhere else; report_html.cpp only renders the result.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/report/flight_volume_sigma.hpp"
#include "pipeline/report/lamp_residuals.hpp"
#include "pipeline/steps/intersection.hpp"

namespace rangecal {

/// Lamp residual RMS over the noise model's expected RMS up to which the residuals are "as the
/// noise model expects" (docs/accuracy_analysis.md).
inline constexpr double kResidualRatioOk = 1.5;
/// Without a flight-volume prediction, a projection σ at the image centre (px) below which weak
/// parameters are harmless for the intersection.
inline constexpr double kHarmlessCentreSigmaPx = 0.5;

/// What the verdict weighs for one calibrated camera.
struct CameraEvidence {
  ResidualConsistency consistency;  ///< its lamp residuals against the noise model
  double centre_sigma_px = std::numeric_limits<double>::quiet_NaN();  ///< projection σ at the image centre
  /// Whether one of its calibration warnings says a parameter is poorly determined or correlated.
  bool weak_parameters = false;
};

/// What the lamp residuals say.
enum class ResidualReading {
  no_residuals,  ///< nothing to judge (no lamp residuals)
  as_expected,   ///< ratio ≤ kResidualRatioOk
  too_large,     ///< beyond: a model error (clock offset, lever arm, heights)
};

/// What a camera's weak parameters mean for the intersection.
enum class WeakParameterEffect {
  none,           ///< no warning of that kind
  harmless,       ///< the combination that places flown points is well determined
  matters,        ///< it is poorly determined
  not_judgeable,  ///< no covariance
};

struct CameraVerdict {
  double residual_ratio = std::numeric_limits<double>::quiet_NaN();  ///< RMS over expected RMS
  ResidualReading reading = ResidualReading::no_residuals;
  WeakParameterEffect weak = WeakParameterEffect::none;
};

/// The check poles against the bar (the config's intersect.bar_mean_dR_m).
struct CheckPoleVerdict {
  IntersectionMeans means;
  bool met = false;  ///< mean ΔR ≤ bar
};

/// `e` judged; `volume` is the flight volume's predicted intersection σ (its median decides the
/// effect of weak parameters when it exists, else the camera's centre σ does).
CameraVerdict judge_camera(const CameraEvidence& e, const SliceStats& volume, double bar_mean_dR_m);

/// The check poles judged; nullopt without intersected poles.
std::optional<CheckPoleVerdict> judge_check_poles(const std::optional<std::vector<IntersectionRow>>& rows,
                                                  double bar_mean_dR_m);

/// Whether the datum (PPK fixes and control), not the images, limits the calibration: the
/// flight volume's σ within kDatumLimitedRatio of its floor (docs/accuracy_analysis.md "Datum floor").
bool datum_limited(const FlightVolumeSigma& v);

}  // namespace rangecal
