#pragma once
// Each camera's lens parameters chosen by evidence (docs/optimisation.md "Lens parameters chosen by
// held-out blocks"). A lens model fitted where the lamp flew is used where the target flies: a term
// the calibration blocks can fit but not pin (k2 on a wide lens seen over part of its image) can
// make the prediction there better or worse, and only a prediction of data the fit has not seen
// tells which. Greedy, one camera at a time in input order: each candidate parameter not already
// free is added to that camera's free set alone and scored twice (pipeline/steps/held_out_prediction.hpp):
// on the time blocks, where it must predict clearly better than the set before it (clearly_better:
// 10× the held-out predictive density), and on the camera's rim (outer_ring_blocks: calibrated
// without the epochs it sees farthest from its principal point, predicting them), where it must
// not predict clearly worse — a polynomial term is most wrong where it is extrapolated. The best
// candidate that passes both is kept, and the next camera is tried against the set with it.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "optim/network/network_options.hpp"
#include "pipeline/steps/held_out_prediction.hpp"

namespace rangecal {

struct LensSelection {
  std::vector<NetworkCamera> cameras;           ///< the problem's cameras, each with its chosen free set
  std::vector<std::vector<std::string>> added;  ///< per camera, the parameters added (in order)
  /// Every scoring: the starting set's on the time blocks first, then per camera its candidates' on
  /// the time blocks, its chosen set's on its rim and its candidates' on its rim.
  std::vector<HeldOutScore> scores;
  bool scored = false;  ///< false: the starting set could not be scored (its `why`); nothing added
};

/// Chooses, for each camera of the network problem (`cameras`, `points`, `observations`), which of
/// `candidates` (free-parameter names, docs/config.md `calibrate.free`) to add to its free set.
/// `options` are the network's, as the run will solve it; `camera_ids` name the cameras in the
/// scores' candidate names ("cam2 + k2").
LensSelection select_lens_parameters(const std::vector<NetworkCamera>& cameras,
                                     const std::vector<NetworkPoint>& points,
                                     const std::vector<NetworkObservation>& observations,
                                     const NetworkOptions& options,
                                     const std::vector<std::string>& candidates,
                                     const std::vector<std::string>& camera_ids,
                                     const HeldOutOptions& held_out = {});

/// run.json `stages.calibrate.counts.lens_selection`: {candidates, added: {camera id: [names]},
/// scores: held_out_scores_json}.
nlohmann::json lens_selection_json(const LensSelection& s, const std::vector<std::string>& candidates,
                                   const std::vector<std::string>& camera_ids);

}  // namespace rangecal
