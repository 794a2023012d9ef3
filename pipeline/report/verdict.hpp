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
/// A clock offset fitted to the lamp residuals (ClockOffsetSignature) beyond this many of its σ is
/// named as a cause of residuals too large; within, the residuals do not show one, and the reading
/// does not send the user after it.
inline constexpr double kClockOffsetSignificance = 3.0;
/// Without a flight-volume prediction, a projection σ at the image centre (px) below which weak
/// parameters are harmless for the intersection.
inline constexpr double kHarmlessCentreSigmaPx = 0.5;

/// What the verdict weighs for one calibrated camera.
struct CameraEvidence {
  ResidualConsistency consistency;  ///< its lamp residuals against the noise model
  double centre_sigma_px = std::numeric_limits<double>::quiet_NaN();  ///< projection σ at the image centre
  /// Whether one of its calibration warnings says a parameter is poorly determined or correlated.
  bool weak_parameters = false;
  /// The clock offset the residuals show, under the same noise model (n = 0: no velocities).
  ClockOffsetSignature clock;
  /// The noise model carries a Gauss–Markov PPK error (a slow wander of the residuals with time is
  /// then the model's, up to its σ_g and τ).
  bool correlated_ppk = false;
};

/// What the lamp residuals say.
enum class ResidualReading {
  no_residuals,  ///< nothing to judge (no lamp residuals)
  as_expected,   ///< ratio ≤ kResidualRatioOk
  too_large,     ///< beyond: a model error (lever arm, heights, PPK error model; a clock offset when shown)
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
  /// too_large, and the residuals follow the lamp's image velocity as a clock offset of
  /// `clock_offset_s` would, beyond kClockOffsetSignificance σ.
  bool clock_offset_shown = false;
  double clock_offset_s = std::numeric_limits<double>::quiet_NaN();
  bool correlated_ppk = false;  ///< CameraEvidence::correlated_ppk
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
