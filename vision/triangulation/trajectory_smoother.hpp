#pragma once
// A continuous-time trajectory from the per-instant fixes (docs/trajectory.md "Smoothing"): a
// constant-acceleration process — the target's jerk white noise of spectral density q (m²/s⁵) on
// each axis (Bar-Shalom, Li & Kirubarajan, "Estimation with Applications to Tracking and
// Navigation", 2001, §6.2.3: the "white noise jerk" model) — observed at every instant by the
// triangulated position with its labels' covariance, smoothed by a Kalman filter and
// Rauch–Tung–Striebel pass over each stretch without a gap. The labels' error is a first-order
// Gauss–Markov process (state-augmented: its variance the instant's labels' covariance, its
// correlation exp(−Δt/τ)): real trackers' errors repeat from frame to frame, and a smoother that
// took them as white would average them down as if independent. q and τ (white, or 1, 2, 4, 8
// median steps) are those of largest innovations' likelihood.
//
// What the smoothing does to each part of σ: the labels' errors are averaged down as far as their
// correlation in time allows; the timing errors are not — a camera's clock offset, its rate and
// its wander move every label of a stretch alike — nor is the calibration's (the same cameras,
// nearly the same rays), so a weighted mean of neighbouring instants carries both whole: their
// parts are kept as they were. Velocity and acceleration come from the smoothed state with its
// covariance (their labels' part: the common errors cancel in a difference to first order).
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "vision/triangulation/target_trajectory.hpp"

namespace rangecal {

struct SmootherOptions {
  /// Instants farther apart than this many median steps lie across a gap: each stretch is
  /// smoothed alone (the process says nothing across a gap).
  double gap_steps = 1.5;
  /// The search range of q (m²/s⁵), log-uniform: from a target at rest to one turning at 100 g
  /// within a few ms.
  double min_jerk_psd = 1e-6, max_jerk_psd = 1e12;
};

struct SmootherReport {
  double jerk_psd = 0;     ///< the q estimated (m²/s⁵)
  double label_tau_s = 0;  ///< the labels' error's time constant chosen (s; 0: white)
  std::size_t stretches = 0;
  /// Instants in stretches of three or more; the others — shorter stretches and instants with a
  /// view outside its calibration's coverage — are left as they were.
  std::size_t smoothed = 0;
};

/// Replaces every point's position, labels' covariance, velocity and its σ by the smoothed ones
/// (the timing and calibration parts kept), and sets its acceleration. Points must be in time
/// order.
SmootherReport smooth_trajectory(Trajectory* trajectory, const SmootherOptions& options = {});

}  // namespace rangecal
