#pragma once
// One observation of a camera calibration (docs/optimisation.md): a world point with its covariance and the
// pixel where the camera saw it, with its σ — a lamp position from the PPK track, or a surveyed
// control pole. The bundle, the LM-QN method, the Monte Carlo and the route planner all take these.
#include <Eigen/Core>
#include <limits>
#include <string>

namespace rangecal {

struct BundleObservation {
  Eigen::Vector3d world = Eigen::Vector3d::Zero();      ///< ENU, m
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();      ///< (u, v), px
  Eigen::Matrix3d world_cov = Eigen::Matrix3d::Zero();  ///< Σ_X, m² (e.g. diag(sdE², sdN², sdU²))
  double pixel_sigma_px = 0;  ///< σ_px of this pixel; ≤ 0 → the method's default
  /// Lamp velocity (ENU, m/s) at the observation's time stamp (Hermite derivative of the track);
  /// zero for static points such as poles. Used only when the clock offset is free (or nonzero).
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  /// Time of the PPK fix the world point comes from (s, one continuous scale per camera): its place
  /// in a correlated PPK error model's Gauss–Markov process (gnss/track/ppk_error_model.hpp,
  /// optim/bundle/correlated_ppk_covariance.hpp). NaN: not a PPK fix (a control pole), its error
  /// independent of every other, as NetworkPoint::time_s.
  double time_s = std::numeric_limits<double>::quiet_NaN();
  /// Where the point came from, for messages: "correspondences line 12", "pole 'P3'
  /// (cam1/poles_px.csv:4)"; may be empty.
  std::string source;
};

/// The world point the camera saw: Xw − v·δ for a camera clock offset δ (s). The world point was
/// interpolated at the frame's stamp, so the lamp really stood at X(stamp − δ) ≈ Xw − v·δ
/// (docs/optimisation.md "Clock offset").
inline Eigen::Vector3d observed_world_point(const BundleObservation& o, double clock_offset_s) {
  return o.world - o.velocity * clock_offset_s;
}

}  // namespace rangecal
