#pragma once
// Whether a camera's distortion is one a lens can have over its image (docs/reliability.md "Input
// ranges"): the distorted → undistorted map F(xd) = xd + Δ(xd) of seed 000 eq. 7 must be
// invertible over the whole image, so that every undistorted point has one distorted image, and
// must stay within the limit below. A calibration read from a file is checked with it before any
// point is projected or triangulated through it (pipeline/io/calibration_json.hpp).
#include <string>

#include "vision/camera/camera_model.hpp"

namespace rangecal {

/// The largest displacement the distortion may give an image point, as a share of the point's
/// distance from the principal point: |Δ(xd)| ≤ kMaxDistortionShare·|xd|. A share of 1 lets a
/// point move as far as it lies from the centre, beyond any lens this model describes (real
/// lenses: a few %, wide-angle ones tens of %), and refuses a unit mistake such as k1 = 1e6 mm⁻².
inline constexpr double kMaxDistortionShare = 1.0;

struct DistortionFault {
  int coefficient = 0;  ///< the term that dominates where the check failed, Distortion::as_array order
  std::string reason;   ///< what is wrong and where (sensor mm, pixels)
};

/// Checks `in`'s distortion over its image ([-0.5, W-0.5] × [-0.5, H-0.5] px): the radial factor
/// r(1 + k1 r² + k2 r⁴ + k3 r⁶) increasing out to the farthest image corner (its derivative
/// 1 + 3k1 r² + 5k2 r⁴ + 7k3 r⁶ > 0), det J_F > 0 at every point of a 65 × 65 grid over the image,
/// and |Δ| within kMaxDistortionShare. Returns true when the distortion passes; else false with
/// `fault` set.
bool distortion_is_physical(const CameraIntrinsics& in, DistortionFault* fault);

}  // namespace rangecal
