#pragma once
// Monte Carlo accuracy analysis of a finished calibration (docs/accuracy_analysis.md; seed 001 §4 and its
// Table 2, taken further; docs/accuracy_analysis.md). The reference calibration is taken as the truth of a
// simulated world: every trial regenerates the exact pixels of the problem's world points through
// the reference camera, adds Gaussian noise to the world points (their PPK covariance) and to the
// pixels (their centroid σ), re-runs the same calibration method, and records every parameter.
// The world noise follows the PPK error model the calibration stated its σ under
// (MonteCarloOptions::ppk_error; docs/accuracy_analysis.md "Monte Carlo"): a white part per point
// and, for a correlated model, one Gauss–Markov sequence per ENU axis over the GNSS epochs' times.
// Per parameter: the mean's offset from the reference (bias_mc), the trials' sd (sd_mc) and the
// reference covariance's σ (sd_predicted), side by side. Optionally, check poles seen by ≥ 2
// cameras are triangulated in every trial from noisy picks (vision/triangulation/triangulation.hpp) and their
// 3-D error compared with the predicted 1σ.
//
// Trials run in parallel (TBB); trial t of camera c draws from its own generator seeded from
// (seed, c, t), and statistics are accumulated in trial order afterwards, so the result is
// identical for any thread count.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "gnss/track/ppk_error_model.hpp"
#include "pipeline/steps/calibration_methods.hpp"
#include "vision/camera/calibration_result.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

/// One camera to re-calibrate: the problem as calibrated and the calibration that came out of it.
struct MonteCarloCamera {
  CalibrationProblem problem;
  CalibrationResult reference;  ///< its camera is the simulated truth, its covariance the prediction
  std::string method;           ///< method to re-run; empty → reference.method
  /// Empty, or one key per problem observation: observations with the same key ≥ 0, in this
  /// camera or another, share one draw of world noise (scaled by each one's own Σ_X) — the same
  /// GNSS epoch or the same surveyed pole seen by several cameras. A negative key: its own draw.
  std::vector<std::int64_t> world_noise_key;
  /// Empty, or one time (s) per problem observation: that of the GNSS epoch whose error it carries,
  /// on one clock for every camera (network_problem's NetworkPoint::time_s, seconds from the lamp
  /// track's first epoch); NaN for a point that is not a PPK fix (a control pole). Empty: the
  /// observations' own time_s. Only a correlated MonteCarloOptions::ppk_error reads it.
  std::vector<double> epoch_time_s;
};

/// A check pole for the intersection statistics: its surveyed position (the simulated truth) and
/// the indices (into the cameras) of the cameras that picked it.
struct MonteCarloPole {
  std::string id;
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();
  std::vector<std::size_t> cameras;
};

struct MonteCarloOptions {
  int trials = 200;            ///< ≥ 1
  std::uint64_t seed = 1;      ///< trial t of camera c is seeded from (seed, c, t)
  bool world_noise = true;     ///< perturb the world points by their covariance
  bool image_noise = true;     ///< perturb the pixels by their σ
  double pick_sigma_px = 0.3;  ///< 1σ per axis of a pole pick (intersection statistics)
  int threads = 0;             ///< 0 = all hardware threads
  /// Use the cameras' world_noise_key (shared epochs and poles); false: every observation of every
  /// camera draws its own world noise (cameras independent, as the triangulation σ assumes).
  bool shared_world_noise = true;
  /// The PPK error model of the world noise (gnss/track/ppk_error_model.hpp): a PPK fix (an
  /// observation with a finite epoch time) draws its white part by S·L·z (S the white scale, L·Lᵀ = Σ_X)
  /// and, when the model is correlated, the Gauss–Markov value of its epoch — one sequence per ENU axis
  /// over the epochs in time order by the exact discretisation (docs/simulator.md "PPK error model"),
  /// one for the epochs every camera shares through world_noise_key and one per camera for its
  /// unkeyed fixes. A point that is not a fix draws by its own Σ_X. The default (S = 1, no GM part)
  /// draws every point by its Σ_X, as the network and the bundle weigh it. A network re-run in the
  /// trials weighs the fixes by this model too (NetworkOptions::ppk_error).
  PpkErrorModel ppk_error;
};

struct ParameterStatistics {
  CameraParameter parameter = CameraParameter::f;  ///< vision/camera/camera_parameters.hpp; its unit
  double estimate = 0;      ///< the reference value (0 for the rotation perturbations wx wy wz)
  double mean = 0;          ///< mean over the successful trials
  double bias_mc = 0;       ///< mean − estimate
  double sd_mc = 0;         ///< sample sd over the successful trials (n − 1)
  double sd_predicted = 0;  ///< from the reference covariance; NaN when it has none
};

struct CameraMonteCarlo {
  std::string camera_id;
  std::string method;
  std::vector<ParameterStatistics> parameters;
  int trials_ok = 0;
  int trials_failed = 0;      ///< calibration errors (degenerate draw); left out of the statistics
  std::string first_failure;  ///< message of the first failed trial, for the log
};

struct PoleMonteCarlo {
  std::string id;
  int n = 0;                                               ///< trials in which it was triangulated
  Eigen::Vector3d mean_error_m = Eigen::Vector3d::Zero();  ///< mean of (triangulated − truth), m
  double rms_error_m = 0;        ///< √mean |ΔR|² (m), to compare with sigma_predicted_m
  double mean_error_norm_m = 0;  ///< mean |ΔR| (m), seed 002 Table 4's statistic
  double max_error_m = 0;
  double sigma_predicted_m = 0;  ///< √trace Σ_X from the reference covariances and pick σ (m)
};

struct MonteCarloResult {
  int trials = 0;
  std::vector<CameraMonteCarlo> cameras;
  std::vector<PoleMonteCarlo> poles;
};

/// Runs the analysis. Cameras whose method is `network` (two or more) are re-run together in every
/// trial: one network (optim/network/network_adjustment.hpp) whose points are the world-noise keys
/// they share, so their statistics are the network's, not the per-camera bundle's.
/// `reference_cross` (indexed by camera, as network.json's cross blocks for the cameras' reference
/// parameters; null or empty: cameras independent) enters the poles' predicted σ and, as the
/// intersect stage's weights, every trial's triangulation of them.
/// Throws rangecal::Error: usage for trials < 1 or a bad pole camera index; calibration when a
/// reference camera cannot project enough of its points or every trial of a camera fails.
MonteCarloResult run_monte_carlo(const std::vector<MonteCarloCamera>& cameras,
                                 const std::vector<MonteCarloPole>& poles, const MonteCarloOptions& options,
                                 const CrossCovariances* reference_cross = nullptr);

/// The world noise of trial `trial` (world point drawn − truth), per camera and per problem
/// observation, exactly as run_monte_carlo adds it; NaN for an observation it does not simulate
/// (an outlier of the reference, or one that does not project through the reference camera). Zero
/// vectors when options.world_noise is false. For checking the draws (their correlation in time).
std::vector<std::vector<Eigen::Vector3d>> monte_carlo_world_noise(
    const std::vector<MonteCarloCamera>& cameras, const MonteCarloOptions& options, std::size_t trial);

/// montecarlo.csv text: `camera,parameter,estimate,bias_mc,sd_mc,sd_predicted`, one row per camera
/// and parameter, 10 significant digits, empty field for a NaN; deterministic.
std::string format_montecarlo_csv(const MonteCarloResult& r);

/// The seed 001 Table 2-style table of one camera (parameter, estimate, bias, sd MC, sd predicted,
/// ratio) for the terminal.
std::string format_montecarlo_table(const CameraMonteCarlo& c);

/// The intersection statistics table (pole, n, mean error E N U, mean |ΔR|, RMS |ΔR|, predicted σ).
std::string format_montecarlo_pole_table(const std::vector<PoleMonteCarlo>& poles);

}  // namespace rangecal
