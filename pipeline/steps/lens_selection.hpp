#pragma once
// Each camera's lens parameters chosen by evidence (docs/optimisation.md "Lens parameters chosen by
// significance and the rim"). A lens model fitted where the lamp flew is used where the target
// flies: a term the data pin (k2 on a wide lens) left out biases every ray near the image's edge,
// while a term they cannot pin, extrapolated, can be worse than none. Greedy, one camera at a time
// in input order: each candidate parameter not already free is added to that camera's free set
// alone and asked two questions:
//   1. significance: solved with every epoch, as the run will solve it, does the parameter differ
//      from the value it was held at by at least kSignificantT of its own σ (scaled by
//      √(variance factor) where that exceeds 1; the t-test of an
//      additional parameter in self-calibration: Gruen & Beyer 2001, "System calibration through
//      self-calibration", in Gruen & Huang (eds.), Calibration and Orientation of Cameras in
//      Computer Vision, Springer)?
//   2. the rim (outer_ring_blocks, pipeline/steps/held_out_prediction.hpp): calibrated without the
//      epochs this camera sees farthest from its principal point and predicting them, does it predict
//      them no clearly worse than the set before it? A polynomial term is most wrong where it is
//      extrapolated.
// Of the candidates that pass both, the most significant is kept, and the next camera is tried
// against the set with it.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "optim/network/network_options.hpp"
#include "pipeline/steps/held_out_prediction.hpp"

namespace rangecal {

/// The |t| a candidate parameter must reach: under the null (the parameter at its held value) t is
/// standard normal where the network's σ holds, so 3 is passed by chance in 0.27 % of the tests.
inline constexpr double kSignificantT = 3;

/// A candidate's significance test: its estimate with every epoch, the value it was held at, its σ.
struct LensSignificance {
  std::string candidate;  ///< "cam2 + k2"
  bool solved = false;    ///< false: the network with it could not be solved or gave it no σ (`why`)
  std::string why;
  /// In the parameter's unit (camera_parameters.hpp); sigma is the network's 1σ scaled by
  /// √(variance factor) where that exceeds 1.
  double value = 0, held_value = 0, sigma = 0;
  double t = 0;  ///< (value − held_value) / sigma
};

struct LensSelection {
  std::vector<NetworkCamera> cameras;           ///< the problem's cameras, each with its chosen free set
  std::vector<std::vector<std::string>> added;  ///< per camera, the parameters added (in order)
  std::vector<LensSignificance> significance;   ///< per camera, each candidate's test
  /// Per camera: its chosen set's rim scoring, then its candidates' (none when it had no candidate).
  std::vector<HeldOutScore> rim_scores;
};

/// Chooses, for each camera of the network problem (`cameras`, `points`, `observations`), which of
/// `candidates` (free-parameter names, docs/config.md `calibrate.free`) to add to its free set.
/// `options` are the network's, as the run will solve it; `camera_ids` name the cameras in the
/// records' candidate names ("cam2 + k2"); `held_out` the rim scoring's options (its blocks are
/// replaced by each camera's rim); `as_given` (per camera, empty: none) the cameras whose free set
/// the user gave (cameras[i].free): not tried.
LensSelection select_lens_parameters(
    const std::vector<NetworkCamera>& cameras, const std::vector<NetworkPoint>& points,
    const std::vector<NetworkObservation>& observations, const NetworkOptions& options,
    const std::vector<std::string>& candidates, const std::vector<std::string>& camera_ids,
    const HeldOutOptions& held_out = {}, const std::vector<bool>& as_given = {});

/// run.json `stages.calibrate.counts.lens_selection`: {candidates, added: {camera id: [names]},
/// significance: [{candidate, solved, why | value, held_value, sigma, t}], rim_scores:
/// held_out_scores_json}.
nlohmann::json lens_selection_json(const LensSelection& s, const std::vector<std::string>& candidates,
                                   const std::vector<std::string>& camera_ids);

}  // namespace rangecal
