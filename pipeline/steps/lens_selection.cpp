#include "pipeline/steps/lens_selection.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "config/error.hpp"
#include "optim/network/network_adjustment.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal {

namespace {

// Question 1: camera c's candidate `name` with every epoch, against the value it was held at. Its σ
// is the network's, scaled by √(variance factor) where that exceeds 1: a σ the residuals show too
// small would make every term look significant (with the image σ estimated the factor is about 1).
LensSignificance significance_of(const HeldOutCandidate& trial, std::size_t c, const std::string& name,
                                 const std::vector<NetworkPoint>& points,
                                 const std::vector<NetworkObservation>& observations) {
  LensSignificance s;
  s.candidate = trial.name;
  const std::optional<CameraParameter> p = parameter_from_name(name);
  if (!p) {
    s.why = "'" + name + "' is not one parameter";
    return s;
  }
  try {
    const NetworkResult r = network_adjust(trial.cameras, points, observations, trial.options);
    const CalibrationResult& cal = r.cameras[c].calibration;
    const double sigma = cal.sigma(*p) * std::sqrt(std::max(1.0, r.statistics.variance_factor));
    if (!(sigma > 0)) {
      s.why = cal.parameter_index(*p) < 0
                  ? "the network did not estimate " + name
                  : "the network's covariance is rank-deficient: " + name + " has no σ";
      return s;
    }
    const NetworkCamera& held = trial.cameras[c];
    s.value = parameter_value(cal.camera, *p, cal.camera, cal.clock_offset_s);
    s.held_value = parameter_value(held.initial, *p, cal.camera, held.options.initial_clock_offset_s);
    s.sigma = sigma;
    s.t = (s.value - s.held_value) / s.sigma;
    s.solved = true;
  } catch (const Error& e) {
    s.why = e.reason();
  }
  return s;
}

}  // namespace

LensSelection select_lens_parameters(const std::vector<NetworkCamera>& cameras,
                                     const std::vector<NetworkPoint>& points,
                                     const std::vector<NetworkObservation>& observations,
                                     const NetworkOptions& options,
                                     const std::vector<std::string>& candidates,
                                     const std::vector<std::string>& camera_ids,
                                     const HeldOutOptions& held_out, const std::vector<bool>& as_given) {
  LensSelection s;
  s.cameras = cameras;
  s.added.resize(cameras.size());
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    if (c < as_given.size() && as_given[c]) continue;
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
    std::vector<LensSignificance> tests;
    for (std::size_t i = 0; i < trials.size(); ++i)
      tests.push_back(significance_of(trials[i], c, names[i], points, observations));
    s.significance.insert(s.significance.end(), tests.begin(), tests.end());
    // Question 2: the same candidates asked for the rim of this camera's image from the rest of it.
    HeldOutOptions rim_options = held_out;
    rim_options.blocks = outer_ring_blocks(cameras, points, observations, c);
    rim_options.both_splits = false;
    std::vector<HeldOutCandidate> rim_trials = trials;
    rim_trials.insert(rim_trials.begin(), {camera_ids[c] + " as chosen", options, s.cameras});
    for (HeldOutCandidate& t : rim_trials) t.name += ", its rim";
    const std::vector<HeldOutScore> rim =
        score_held_out_blocks(cameras, points, observations, rim_trials, rim_options);
    s.rim_scores.insert(s.rim_scores.end(), rim.begin(), rim.end());
    std::size_t pick = trials.size();
    for (std::size_t i = 0; i < trials.size(); ++i)
      if (tests[i].solved && std::abs(tests[i].t) >= kSignificantT && !clearly_better(rim[0], rim[i + 1]) &&
          (pick == trials.size() || std::abs(tests[i].t) > std::abs(tests[pick].t)))
        pick = i;
    if (pick == trials.size()) continue;
    s.cameras[c] = trials[pick].cameras[c];
    s.added[c].push_back(names[pick]);
  }
  return s;
}

nlohmann::json lens_selection_json(const LensSelection& s, const std::vector<std::string>& candidates,
                                   const std::vector<std::string>& camera_ids) {
  nlohmann::json added = nlohmann::json::object();
  for (std::size_t c = 0; c < s.added.size() && c < camera_ids.size(); ++c) added[camera_ids[c]] = s.added[c];
  nlohmann::json tests = nlohmann::json::array();
  for (const LensSignificance& t : s.significance) {
    nlohmann::json j = {{"candidate", t.candidate}, {"solved", t.solved}};
    if (!t.solved) {
      j["why"] = t.why;
    } else {
      j["value"] = t.value;
      j["held_value"] = t.held_value;
      j["sigma"] = t.sigma;
      j["t"] = t.t;
    }
    tests.push_back(j);
  }
  return {{"candidates", candidates},
          {"added", added},
          {"significance", tests},
          {"rim_scores", held_out_scores_json(s.rim_scores)}};
}

}  // namespace rangecal
