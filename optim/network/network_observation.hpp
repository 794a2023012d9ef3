#pragma once
// The network's data (docs/optimisation.md "Network bundle"): points — one per used lamp epoch,
// with its PPK fix and covariance as a prior, and one per control pole with its survey prior —
// and image observations, each tying one camera to one point.
//
// A camera does not see the epoch's position itself but the lamp at its own frame time: the
// observation carries the Hermite interpolant's displacement from the epoch to the frame stamp
// (≈ v·(t_frame − t_epoch), a few cm at most) and the velocity there, so the point it sees is
//   X_seen = X_k + offset − v·δ_c                  (δ_c the camera's clock offset)
// (optim/bundle/bundle_observation.hpp for the clock-offset term).
#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <string>

namespace rangecal {

/// One network point: a lamp epoch or a control pole top.
struct NetworkPoint {
  /// PPK fix of the epoch (lamp centre) or surveyed pole top, ENU m.
  Eigen::Vector3d prior_enu = Eigen::Vector3d::Zero();
  /// Its covariance (m²): the full 3×3 of the .pos sd and sdne/sdeu/sdun columns rotated to ENU, or
  /// the survey σ² per axis. Must be positive definite.
  Eigen::Matrix3d prior_cov = Eigen::Matrix3d::Identity() * 1e-4;
  bool control_pole = false;  ///< a pole never takes part in the PPK outlier test
  int quality = 1;            ///< RTKLIB Q of the epoch (1 fix, 2 float); 0 for poles
  /// The epoch's time (s, on one continuous scale for the whole mission): its place in the PPK
  /// error's Gauss–Markov chain (gnss/track/ppk_error_model.hpp). NaN: not a PPK epoch (a pole, a lone pair),
  /// outside the chain, its prior white.
  double time_s = std::numeric_limits<double>::quiet_NaN();
  std::string source;  ///< for messages: "epoch 2024-… (lamp_track.csv line 12)", "pole 'P3'"
};

/// One camera's view of one point.
struct NetworkObservation {
  std::size_t camera = 0;                           ///< index into the network's cameras
  std::size_t point = 0;                            ///< index into the network's points
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  ///< (u, v), px
  double pixel_sigma_px = 0;                        ///< ≤ 0 → the camera's BundleOptions::pixel_sigma_px
  /// Lamp at the frame stamp − lamp at the epoch (interpolant, ENU m); zero for poles.
  Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();
  /// Lamp velocity at the frame stamp (ENU m/s); zero for poles.
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  std::string source;  ///< for messages, e.g. "cam1 correspondences line 12"
};

/// X_seen = X + offset − v·δ (m), δ the camera's clock offset (s).
inline Eigen::Vector3d network_seen_point(const Eigen::Vector3d& X, const NetworkObservation& o,
                                          double clock_offset_s) {
  return X + o.offset_m - o.velocity * clock_offset_s;
}

}  // namespace rangecal
