#pragma once
// The network a scenario would give (docs/accuracy_analysis.md `plan`; docs/accuracy_analysis.md): one point
// per fix GNSS epoch that some camera sees (the align stage's nearest frame within align.max_frame_offset_s,
// lamp in view), at the true lamp position with the epoch's PPK covariance, and each camera's view of it —
// the exact pixel, the lamp's displacement from the epoch to the frame and its velocity there; then, when the
// mission calibrates with control poles, each control pole top in view under its survey σ with the pick σ.
// Noise-free: the priors are the truth (a Monte Carlo adds the noise), so the Cramér–Rao bound can be
// evaluated here.
#include <vector>

#include "optim/network/network_observation.hpp"
#include "optim/network/network_options.hpp"
#include "pipeline/analysis/camera_bound.hpp"
#include "pipeline/simulate/mission_simulator.hpp"
#include "pipeline/simulate/scenario.hpp"

namespace rangecal {

struct PlannedNetwork {
  std::vector<Camera> truth;  ///< per scenario camera
  std::vector<NetworkPoint> points;
  std::vector<NetworkObservation> observations;
  /// The scenario's PPK errors as the network would weigh them (stated_error_model): the bound is
  /// then the correlated one when the scenario draws a Gauss–Markov part.
  PpkErrorModel ppk;
  /// Per camera its priors as the calibrate stage would give them (empty: none; with_survey).
  std::vector<BundlePriors> priors;
};

PlannedNetwork planned_network(const Scenario& s, const PlanOptions& options = {});

/// The same from a mission already simulated (`rangecal plan` simulates each candidate once).
PlannedNetwork planned_network(const SimMission& m, const PlanOptions& options = {});

/// `n` as if surveyed differently (docs/accuracy_analysis.md "What surveying buys"): its control poles
/// replaced by the first `control_poles` of the scenario's poles (those with role control first, then
/// the others, each in scenario order; fewer when the scenario has fewer), whatever the mission's
/// use_control_poles, each under the scenario's survey σ and pick σ; and, when `station_sigma_m` > 0,
/// every camera centre held at its true position by a prior of that σ per axis.
PlannedNetwork with_survey(const PlannedNetwork& n, const Scenario& s, std::size_t control_poles,
                           double station_sigma_m);

/// The network's Cramér–Rao bound of every camera's parameters named by `free` (the joint Fisher
/// information with the points eliminated: the Schur complement of the noise-free network at the
/// truth, optim/network/network_covariance.hpp; the cameras' `priors` included): the joint covariance,
/// cameras in order. Every image
/// σ (each observation's, else `pixel_sigma_px`) is divided by `image_factor`
/// (kDatumFloorImageFactor: the datum floor).
Eigen::MatrixXd network_cramer_rao_bound(const PlannedNetwork& n, const std::vector<std::string>& free,
                                         double pixel_sigma_px, double image_factor = 1);

}  // namespace rangecal
