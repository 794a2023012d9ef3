#include "pipeline/steps/lens_selection.hpp"

#include <algorithm>

namespace rangecal {

LensSelection select_lens_parameters(const std::vector<NetworkCamera>& cameras,
                                     const std::vector<NetworkPoint>& points,
                                     const std::vector<NetworkObservation>& observations,
                                     const NetworkOptions& options,
                                     const std::vector<std::string>& candidates,
                                     const std::vector<std::string>& camera_ids,
                                     const HeldOutOptions& held_out) {
  LensSelection s;
  s.cameras = cameras;
  s.added.resize(cameras.size());
  HeldOutScore best =
      score_held_out_blocks(cameras, points, observations, {{"starting set", options, {}}}, held_out)[0];
  s.scores.push_back(best);
  s.scored = best.scored;
  if (!s.scored) return s;
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    std::vector<HeldOutCandidate> trials;
    std::vector<std::string> names;
    for (const std::string& p : candidates) {
      const std::vector<std::string>& free = s.cameras[c].options.free;
      if (std::find(free.begin(), free.end(), p) != free.end()) continue;
      HeldOutCandidate t{camera_ids[c] + " + " + p, options, s.cameras};
      t.cameras[c].options.free.push_back(p);
      trials.push_back(std::move(t));
      names.push_back(p);
    }
    if (trials.empty()) continue;
    const std::vector<HeldOutScore> scores =
        score_held_out_blocks(cameras, points, observations, trials, held_out);
    s.scores.insert(s.scores.end(), scores.begin(), scores.end());
    // The same candidates asked for the rim of this camera's image from the rest of it.
    HeldOutOptions rim_options = held_out;
    rim_options.blocks = outer_ring_blocks(cameras, points, observations, c);
    rim_options.both_splits = false;
    std::vector<HeldOutCandidate> rim_trials = trials;
    rim_trials.insert(rim_trials.begin(), {camera_ids[c] + " as chosen", options, s.cameras});
    for (HeldOutCandidate& t : rim_trials) t.name += ", its rim";
    const std::vector<HeldOutScore> rim =
        score_held_out_blocks(cameras, points, observations, rim_trials, rim_options);
    s.scores.insert(s.scores.end(), rim.begin(), rim.end());
    std::size_t pick = scores.size();
    for (std::size_t i = 0; i < scores.size(); ++i)
      if (clearly_better(scores[i], best) && !clearly_better(rim[0], rim[i + 1]) &&
          (pick == scores.size() || scores[i].score < scores[pick].score))
        pick = i;
    if (pick == scores.size()) continue;
    s.cameras[c] = trials[pick].cameras[c];
    s.added[c].push_back(names[pick]);
    best = scores[pick];
  }
  return s;
}

nlohmann::json lens_selection_json(const LensSelection& s, const std::vector<std::string>& candidates,
                                   const std::vector<std::string>& camera_ids) {
  nlohmann::json added = nlohmann::json::object();
  for (std::size_t c = 0; c < s.added.size() && c < camera_ids.size(); ++c) added[camera_ids[c]] = s.added[c];
  return {{"candidates", candidates}, {"added", added}, {"scores", held_out_scores_json(s.scores)}};
}

}  // namespace rangecal
