#pragma once
// The network's model chosen by evidence (docs/optimisation.md "Held-out blocks"): each candidate
// error model calibrates the cameras on alternate blocks of lamp epochs and predicts the others.
//
// The lamp epochs are cut into `block_s` blocks of time from the first; split 0 calibrates on the
// even blocks and predicts the odd ones, split 1 the reverse (control poles and pairs without an
// epoch calibrate in both). For each held-out epoch seen by two or more cameras, the point is
// triangulated from the pixels (vision/triangulation: the cameras' network covariance, cross terms
// included, and each camera's pixel σ as the candidate estimated it; each camera's view shifted by
// its observation's displacement from the epoch to its frame) and compared with the epoch's fix:
//   d = X − fix,   C = Σ_X + Σ_fix,   Σ_fix = S·Σ_pos·S + diag(σ_g²)  (the candidate's marginal)
//   z² = dᵀC⁻¹d / 3,    score = mean over epochs of (dᵀC⁻¹d + ln det C)
// The score is the negative log predictive density up to a constant: it rewards a small error and a
// σ that covers it, and punishes a σ that claims more than the error shows — what neither the rms
// nor the likelihood of the calibration blocks alone can tell. The fix's error is not independent
// of the calibration blocks' under a Gauss–Markov model; the score treats it as if it were (its
// covariance only), which favours no candidate.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "optim/network/network_observation.hpp"
#include "optim/network/network_options.hpp"

namespace rangecal {

struct HeldOutOptions {
  double block_s = 15;          ///< block length (s)
  std::size_t min_epochs = 20;  ///< held-out epochs (≥ 2 cameras) needed in each split
  /// Per point (empty: none): not scored as a held-out epoch. The calibrate stage gives the fixes
  /// the whole mission's network rejected as PPK outliers: a fix known wrong tests no prediction.
  std::vector<bool> not_scored;
  /// Per point (empty: the time blocks above): its block, given. Points of even blocks (and of a
  /// negative one: always calibrating) calibrate split 0, odd ones are predicted; with
  /// `both_splits` the reverse is split 1.
  std::vector<long> blocks;
  bool both_splits = true;
};

/// One candidate: a name for the record, the network's options it calibrates with and, when not
/// empty, its own cameras (a free set of its own; else the cameras given to the scoring).
struct HeldOutCandidate {
  std::string name;
  NetworkOptions options;
  std::vector<NetworkCamera> cameras;
};

/// A candidate's prediction of the held-out epochs, pooled over both splits.
struct HeldOutScore {
  std::string candidate;
  bool scored = false;  ///< false: a split failed or had too few epochs (`why`)
  std::string why;
  std::size_t epochs = 0;  ///< held-out epochs triangulated, both splits
  double rms_m = 0;        ///< √(mean |d|²)
  double median_m = 0;     ///< median |d|
  double sigma_rms_m = 0;  ///< √(mean trace C): the σ the candidate states for them
  double z_rms = 0;        ///< √(mean z²): 1 when the σ holds
  double score = 0;        ///< mean (dᵀC⁻¹d + ln det C), ln of m²; lower is better
};

/// Scores each candidate on the network's cameras, points and observations (method in the header
/// comment). Never throws for a candidate that cannot be solved on a split: it is returned unscored
/// with the reason.
std::vector<HeldOutScore> score_held_out_blocks(const std::vector<NetworkCamera>& cameras,
                                                const std::vector<NetworkPoint>& points,
                                                const std::vector<NetworkObservation>& observations,
                                                const std::vector<HeldOutCandidate>& candidates,
                                                const HeldOutOptions& options = {});

/// The blocks of an extrapolation test for camera `camera` (HeldOutOptions::blocks): 1 for each point
/// whose observation in that camera lies farther from its starting principal point than the
/// (1 − outer_share) quantile of its lamp observations' distances, 0 for the other points with a
/// time, −1 for the rest. Calibrated on
/// block 0 and predicting block 1 (both_splits false), a lens model is asked for the image's rim
/// from the rest of the image: its extrapolation.
std::vector<long> outer_ring_blocks(const std::vector<NetworkCamera>& cameras,
                                    const std::vector<NetworkPoint>& points,
                                    const std::vector<NetworkObservation>& observations, std::size_t camera,
                                    double outer_share = 0.2);

/// The evidence a choice between candidates asks for: `b`'s held-out predictive density at least
/// kHeldOutDensityRatio times `a`'s over their epochs. The score is −2 ln p per epoch up to a
/// constant, so the test is n·(score_a − score_b) ≥ 2 ln 10 (Jeffreys' "strong" evidence). A score
/// merely lower is no evidence.
inline constexpr double kHeldOutDensityRatio = 10;
bool clearly_better(const HeldOutScore& b, const HeldOutScore& a);

/// run.json `stages.calibrate.counts.held_out`: one object per candidate, {candidate, scored, why |
/// epochs, rms_m, median_m, sigma_rms_m, z_rms, score}.
nlohmann::json held_out_scores_json(const std::vector<HeldOutScore>& scores);

}  // namespace rangecal
