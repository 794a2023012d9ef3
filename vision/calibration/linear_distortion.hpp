#pragma once
// Linear least-squares distortion initial values (seed 000 eq. 8; seed 001 eqs. 14–16), given a
// camera estimated without distortion (DLT, homography method). Distortion is docs/conventions.md's
// distorted → undistorted correction Δ of vision/camera/camera_model.hpp (seed 000 eq. 7), sensor mm.
#include <array>
#include <utility>
#include <vector>

#include "vision/calibration/point_correspondence.hpp"
#include "vision/camera/camera_model.hpp"

namespace rangecal {

/// Which of the 7 distortion terms (Distortion::as_array() order: k1 k2 k3 p1 p2 a1 a2) to estimate.
using DistortionTerms = std::array<bool, 7>;
inline constexpr DistortionTerms kRadialK1{true, false, false, false, false, false, false};
inline constexpr DistortionTerms kRadialK1K2{true, true, false, false, false, false, false};
inline constexpr DistortionTerms kAllDistortionTerms{true, true, true, true, true, true, true};

struct LinearDistortionFit {
  Distortion dist;           ///< estimated terms; the others 0
  double rms_before_mm = 0;  ///< RMS of Δ = undistorted(model) − distorted(observed), sensor mm, per axis
  double rms_after_mm = 0;   ///< RMS of Δ − D·k after the fit
};

/// Linear least-squares distortion initial values given a camera without distortion (seed 000 eq. 8;
/// seed 001 eqs. 14–16 for k1, k2): for every point, xd, yd = observed pixel → sensor mm about
/// (u0, v0); xu, yu = f·Xc/Zc from the camera; D·k = [xu − xd, yu − yd] with D's rows the
/// derivatives of camera_model.hpp's Δ (eq. 7, distorted → undistorted). `views` pairs each pose with
/// its points (one pose for a single camera; one per view for the planar method); the intrinsics'
/// own distortion is ignored. Columns are equilibrated before the SVD solve; throws (calibration)
/// on a rank-deficient system or fewer equations than terms.
LinearDistortionFit fit_linear_distortion(
    const CameraIntrinsics& intr,
    const std::vector<std::pair<CameraPose, std::vector<PointCorrespondence>>>& views,
    const DistortionTerms& terms);
/// Single-camera convenience.
LinearDistortionFit fit_linear_distortion(const Camera& cam, const std::vector<PointCorrespondence>& pts,
                                          const DistortionTerms& terms);

}  // namespace rangecal
