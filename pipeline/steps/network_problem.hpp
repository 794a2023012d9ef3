#pragma once
// The calibrate stage's network (docs/optimisation.md "Network bundle"): the cameras' calibration
// problems joined through the lamp-track epochs they share. Each lamp pair is keyed to the epoch of
// gnss/lamp_track.csv nearest its frame (within align.max_frame_offset_s, as the align stage
// picked it); the epoch's point carries the fix and its covariance as the prior, the pair the
// interpolant's displacement from the epoch to its frame (pair ENU − epoch ENU) and the velocity.
// Each `control` pole becomes one point under its survey prior (calibrate.control_sigma_m per axis), seen
// by every camera that picked it; check poles never enter. A pair with no epoch near it (a track
// read without it) becomes a point of its own: it cannot tie cameras together, and calibrates its
// camera as the per-camera bundle would.
#include <string>
#include <vector>

#include "gnss/track/lamp_track.hpp"
#include "optim/network/network_observation.hpp"
#include "optim/network/network_options.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/steps/calibration_problem.hpp"

namespace rangecal {

/// One camera's part: its problem (observations: lamp pairs, then control poles) and its pairs.
struct NetworkCameraInput {
  const CalibrationProblem* problem = nullptr;
  const std::vector<Correspondence>* pairs = nullptr;
  Camera start;  ///< starting camera (the per-camera bundle's result)
  double start_clock_offset_s = 0;
};

struct NetworkProblem {
  std::vector<NetworkCamera> cameras;
  std::vector<NetworkPoint> points;
  std::vector<NetworkObservation> observations;
  /// Per point: the lamp-track epoch it is (index into the track), or −1 (a pole or a lone pair).
  std::vector<long> epoch_of_point;
};

/// One camera of the network: its free set, pixel σ and priors as its problem states them,
/// started at `start` with clock offset `start_clock_offset_s` (s).
NetworkCamera network_camera(const CalibrationProblem& p, const Camera& start, double start_clock_offset_s);

/// Builds the network. `max_frame_offset_s` (s) bounds the pair–epoch pairing.
NetworkProblem make_network_problem(const std::vector<NetworkCameraInput>& cameras, const LampTrack& track,
                                    double max_frame_offset_s);

/// Number of lamp-track epochs seen by two or more of the network's cameras: the epochs that tie
/// cameras together. Zero means the network reduces to each camera's own bundle (the calibrate
/// stage's default-method rule, docs/config.md).
std::size_t shared_epoch_count(const NetworkProblem& n);

}  // namespace rangecal
