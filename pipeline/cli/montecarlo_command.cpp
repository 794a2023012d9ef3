// `rangecal montecarlo CONFIG [--trials N] [--seed S] [--threads T] [--pick-sigma PX]` (docs/cli.md,
// §7): re-runs the calibration of a finished mission (each camera's correspondences.csv and
// calibration.json) under simulated noise (pipeline/analysis/monte_carlo.hpp), prints a seed 001
// Table 2-style table per camera and the check poles' intersection statistics, and writes
// `<out>/montecarlo.csv`. The world noise is drawn under the PPK error model the calibrations state
// their σ under (reference_error_model). docs/accuracy_analysis.md.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "config/atomic_file.hpp"
#include "config/error.hpp"
#include "gnss/formats/lamp_track_csv.hpp"
#include "gnss/formats/pole_survey_csv.hpp"
#include "pipeline/analysis/monte_carlo.hpp"
#include "pipeline/cli/commands.hpp"
#include "pipeline/io/calibration_json.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/network_json.hpp"
#include "pipeline/io/output_paths.hpp"
#include "pipeline/io/stated_ppk_error_model.hpp"
#include "pipeline/steps/calibration_problem.hpp"

namespace rangecal {
namespace {

/// Check poles picked in ≥ 2 of the cameras, for the intersection statistics.
std::vector<MonteCarloPole> check_poles(const MissionConfig& cfg) {
  std::vector<MonteCarloPole> out;
  if (cfg.poles_file.empty() || cfg.cameras.size() < 2) return out;
  std::map<std::string, std::vector<std::size_t>> seen_by;
  for (std::size_t c = 0; c < cfg.cameras.size(); ++c) {
    if (cfg.cameras[c].pole_observations.empty()) continue;
    for (const PolePick& pick :
         read_pole_picks(cfg.cameras[c].pole_observations,
                         {cfg.cameras[c].sensor.width_px, cfg.cameras[c].sensor.height_px}))
      seen_by[pick.id].push_back(c);
  }
  for (const SurveyedPole& p : read_pole_survey(cfg.poles_file, cfg.origin)) {
    if (p.role != PoleRole::check) continue;
    const auto it = seen_by.find(p.id);
    if (it == seen_by.end() || it->second.size() < 2) continue;
    out.push_back({p.id, p.enu, it->second});
  }
  return out;
}

/// World-noise keys of one camera's problem (pipeline/analysis/monte_carlo.hpp): a lamp pair gets the index
/// of the lamp-track epoch nearest its frame (the GNSS epoch whose error it carries: the align stage
/// keeps frames within a few ms of an epoch), a control pole kPoleKeyBase + a number per pole id,
/// the same in every camera (`pole_keys`, filled as ids appear). Without a track every lamp pair
/// keeps −1 (its own draw).
constexpr std::int64_t kPoleKeyBase = std::int64_t{1} << 40;

/// Per observation of one camera's problem, the time of the epoch its world-noise key names: seconds
/// from the track's first epoch, as the network places its epochs in the Gauss–Markov chain
/// (pipeline/steps/network_problem.hpp); NaN for a control pole. Empty without a track (the
/// observations' own times then).
std::vector<double> epoch_times(const CalibrationProblem& problem, const std::vector<std::int64_t>& keys,
                                std::size_t lamp_pairs, const LampTrack* track) {
  if (!track || track->epochs.empty()) return {};
  std::vector<double> t(problem.observations.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < lamp_pairs && i < t.size(); ++i)
    t[i] = 1e-9 * static_cast<double>(track->epochs[static_cast<std::size_t>(keys[i])].utc.ns -
                                      track->epochs.front().utc.ns);
  return t;
}

/// The PPK error model of the world noise (MonteCarloOptions::ppk_error): the one the reference
/// calibrations record (all that record one must agree; `paths` their files), else the mission's
/// gnss.error_model (a bundle under its own weighting records none). Notes on stderr, unless
/// `quiet`, the cameras whose σ are not stated under a model other than white (a method that does
/// not read it), whose sd_predicted then stays white.
PpkErrorModel reference_error_model(const MissionConfig& cfg, const std::vector<MonteCarloCamera>& cams,
                                    const std::vector<std::string>& paths, bool quiet) {
  std::optional<PpkErrorModel> model;
  std::string model_path;
  std::vector<std::string> unstated;
  for (std::size_t c = 0; c < cams.size(); ++c) {
    const std::optional<StatedPpkErrorModel> m = stated_ppk_error_model(cams[c].reference, paths[c]);
    if (!m) {
      unstated.push_back(cams[c].problem.camera_id + " (" + cams[c].reference.method + ")");
      continue;
    }
    if (model && !same_ppk_error_model(*model, m->model))
      throw_input_error(paths[c], 0, m->field,
                        "another PPK error model than " + model_path +
                            "'s; the cameras of one mission are calibrated under one model (re-run "
                            "`rangecal calibrate CONFIG`)");
    model = m->model;
    model_path = paths[c];
  }
  const PpkErrorModel out = model ? *model : cfg.gnss.error_model;
  if (!quiet && out.correlated())
    for (const std::string& u : unstated)
      std::cerr << "montecarlo: camera " << u
                << " records no PPK error model: its sd_predicted is not stated under the correlated "
                   "model the world noise is drawn under\n";
  return out;
}

std::vector<std::int64_t> world_noise_keys(const CalibrationProblem& problem,
                                           const std::vector<Correspondence>& pairs, const LampTrack* track,
                                           std::map<std::string, std::int64_t>* pole_keys) {
  std::vector<std::int64_t> keys(problem.observations.size(), -1);
  if (track && !track->epochs.empty())
    for (std::size_t i = 0; i < pairs.size(); ++i)
      keys[i] = static_cast<std::int64_t>(
          nearest_in_time(track->epochs, pairs[i].utc, [](const LampEpoch& e) { return e.utc; }));
  const std::size_t first_pole = problem.observations.size() - problem.control_pole_ids.size();
  for (std::size_t k = 0; k < problem.control_pole_ids.size(); ++k) {
    const auto [it, added] = pole_keys->emplace(problem.control_pole_ids[k],
                                                kPoleKeyBase + static_cast<std::int64_t>(pole_keys->size()));
    keys[first_pole + k] = it->second;
  }
  return keys;
}

}  // namespace

void add_montecarlo_command(CLI::App& app, const CliContext& ctx) {
  struct Args {
    std::string config;
    int trials = 200;
    long long seed = -1;
    int threads = 0;
    double pick_sigma_px = 0;  ///< 0: the config's intersect.pick_sigma_px
    bool independent = false;  ///< every camera its own world noise (no shared epochs or poles)
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand(
      "montecarlo",
      "Monte Carlo accuracy of a finished calibration: bias and sd per parameter next to the "
      "covariance σ (writes montecarlo.csv)");
  sub->add_option("CONFIG", args->config, "Mission config (JSON) of a calibrated mission")->required();
  sub->add_option("--trials", args->trials, "Number of trials (≥ 1; default 200)");
  sub->add_option("--seed", args->seed, "Seed of the noise (default calibrate.seed)");
  sub->add_option("--threads", args->threads, "Worker threads (0 = all; results do not depend on it)");
  sub->add_option("--pick-sigma", args->pick_sigma_px,
                  "1σ of a pole pick per axis, px (default: the config's intersect.pick_sigma_px)");
  sub->add_flag("--independent-cameras", args->independent,
                "Draw every camera's world noise independently (default: cameras that saw the same GNSS "
                "epoch or control pole share its error, as in a real mission)");
  sub->callback([args, &ctx]() {
    // 10⁵ trials give σ to 0.2 %; more is hours of work that changes nothing.
    if (args->trials < 1 || args->trials > 100000)
      throw_config_error("", "--trials", "must be in [1, 100000], got " + std::to_string(args->trials));
    if (args->threads < 0 || args->threads > 1024)
      throw_config_error("", "--threads", "must be in [0, 1024], got " + std::to_string(args->threads));
    if (args->pick_sigma_px < 0 || !std::isfinite(args->pick_sigma_px))
      throw_config_error("", "--pick-sigma", "must be positive");
    const MissionConfig cfg = load_mission_config(args->config);
    std::optional<LampTrack> track;
    if (std::filesystem::exists(lamp_track_path(cfg))) track = read_lamp_track_csv(lamp_track_path(cfg));
    std::vector<MonteCarloCamera> cams;
    std::map<std::string, std::int64_t> pole_keys;
    std::vector<std::string> calibration_paths;
    for (const CameraConfig& cam : cfg.cameras) {
      const std::string corr = camera_output(cfg, cam.id, kCorrespondencesCsv);
      const std::string cal = camera_output(cfg, cam.id, kCalibrationJson);
      if (!std::filesystem::exists(corr))
        throw_input_error(corr, 0, "",
                          "missing; montecarlo re-runs a finished calibration (run the "
                          "detect and calibrate stages first)");
      if (!std::filesystem::exists(cal))
        throw_input_error(cal, 0, "",
                          "missing; montecarlo needs the reference calibration (run "
                          "`rangecal calibrate CONFIG` first)");
      MonteCarloCamera m;
      const std::vector<Correspondence> pairs = read_correspondences_csv(corr);
      m.problem = make_calibration_problem(cam, cfg.calibrate, pairs, read_control_pole_views(cfg, cam));
      m.reference = read_calibration_json(cal);
      m.world_noise_key = world_noise_keys(m.problem, pairs, track ? &*track : nullptr, &pole_keys);
      m.epoch_time_s = epoch_times(m.problem, m.world_noise_key, pairs.size(), track ? &*track : nullptr);
      cams.push_back(std::move(m));
      calibration_paths.push_back(cal);
    }
    MonteCarloOptions o;
    o.trials = args->trials;
    o.seed = args->seed >= 0 ? static_cast<std::uint64_t>(args->seed) : cfg.calibrate.seed;
    o.threads = args->threads;
    o.pick_sigma_px = args->pick_sigma_px > 0 ? args->pick_sigma_px : cfg.intersect.pick_sigma_px;
    o.shared_world_noise = !args->independent;
    o.ppk_error = reference_error_model(cfg, cams, calibration_paths, ctx.quiet);
    if (!track && !ctx.quiet)
      std::cerr << "montecarlo: no " << lamp_track_path(cfg)
                << ": the lamp points' noise is drawn independently per camera\n";
    // Network calibrations are correlated: the poles' predicted σ takes network.json's cross blocks
    // (as the intersect stage does, docs/intersection.md).
    CrossCovariances cross;
    std::vector<std::string> ids;
    std::vector<std::vector<CameraParameter>> parameters;
    bool all_network = cams.size() >= 2;
    for (const MonteCarloCamera& m : cams) {
      ids.push_back(m.problem.camera_id);
      parameters.push_back(m.reference.parameters);
      all_network = all_network && m.reference.method == "network";
    }
    if (all_network)
      cross = read_network_cross_covariances(mission_output(cfg, "network.json"), ids, &parameters);
    const MonteCarloResult r = run_monte_carlo(cams, check_poles(cfg), o, &cross);
    write_file_atomic(mission_output(cfg, kMonteCarloCsv), format_montecarlo_csv(r));
    if (ctx.quiet) return;
    for (const CameraMonteCarlo& c : r.cameras) {
      std::cout << format_montecarlo_table(c);
      if (!c.first_failure.empty()) std::cout << "  first failed trial: " << c.first_failure << "\n";
    }
    if (!r.poles.empty()) std::cout << format_montecarlo_pole_table(r.poles);
    std::cout << "wrote " << mission_output(cfg, kMonteCarloCsv) << "\n";
  });
}

}  // namespace rangecal
