#include "pipeline/analysis/monte_carlo.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>

#include "config/deterministic_random.hpp"
#include "config/error.hpp"
#include "config/number_format.hpp"
#include "optim/network/network_adjustment.hpp"
#include "pipeline/simulate/ppk_error.hpp"
#include "pipeline/steps/network_problem.hpp"
#include "vision/triangulation/calibration_covariance.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Each trial draws from streams seeded by mix_seed (config/deterministic_random.hpp): camera c's
// noise from (seed, c, trial), the pole picks from (seed, kPoleStream, trial), the noise of
// world-noise key k from (seed, kWorldStream, trial, k) and Gauss–Markov chain k from
// (seed, kGaussMarkovStream, trial, k) — the same on every platform and for any thread count.
constexpr std::uint64_t kPoleStream = 0x706F6C6573ull;   // "poles": pick noise, apart from cameras
constexpr std::uint64_t kWorldStream = 0x776F726C64ull;  // "world": keyed world noise, shared by cameras
constexpr std::uint64_t kGaussMarkovStream = 0x676D61726Bull;  // "gmark": the PPK errors' GM part

/// The standard normal 3-vector of world-noise key `key` in trial `trial`: every camera that
/// observed that epoch (or pole) draws the same vector, whatever the thread or camera order.
Eigen::Vector3d keyed_normal3(std::uint64_t seed, std::size_t trial, std::int64_t key) {
  DeterministicRandom r(mix_seed(seed, kWorldStream, trial, static_cast<std::uint64_t>(key)));
  const double a = r.normal(), b = r.normal(), c = r.normal();
  return {a, b, c};
}

/// The simulated truth of one camera: the reference camera, the observations it keeps (not
/// rejected as outliers, projecting) with their exact pixels, and the factors of their white world
/// noise.
struct CameraTruth {
  std::vector<BundleObservation> observations;  ///< world = truth, pixel = exact projection
  std::vector<Eigen::Matrix3d> world_factor;    ///< L with L·Lᵀ = Σ_X; S·L for a PPK fix under S ≠ 1
  std::vector<double> pixel_sigma;
  std::vector<std::int64_t> key;   ///< world-noise key per kept observation (−1: own draw)
  std::vector<double> time_s;      ///< epoch time per kept observation; NaN: not a PPK fix
  std::vector<std::size_t> index;  ///< the problem observation each kept one is
  std::vector<CameraParameter> parameters;
  std::string method;
};

CameraTruth make_truth(const MonteCarloCamera& c, bool shared, const PpkErrorModel& model) {
  const std::size_t n = c.problem.observations.size();
  for (const auto& [name, size] :
       {std::pair<const char*, std::size_t>{"world_noise_key", c.world_noise_key.size()},
        {"epoch_time_s", c.epoch_time_s.size()}})
    if (size != 0 && size != n)
      throw_config_error("", name,
                         "camera " + c.problem.camera_id + " has " + std::to_string(size) + " entries for " +
                             std::to_string(n) + " observations");
  // The white part of a fix is S·Σ_X·S (gnss/track/ppk_error_model.hpp); S = 1 leaves L as it is.
  const bool scaled = model.white_scale_h != 1 || model.white_scale_v != 1;
  const Eigen::Matrix3d S = model.white_scale().asDiagonal();
  CameraTruth t;
  t.method = c.method.empty() ? c.reference.method : c.method;
  t.parameters =
      c.reference.parameters.empty() ? expand_free_parameters(c.problem.free) : c.reference.parameters;
  std::vector<bool> rejected(c.problem.observations.size(), false);
  for (std::size_t i : c.reference.rejected)
    if (i < rejected.size()) rejected[i] = true;
  for (std::size_t i = 0; i < c.problem.observations.size(); ++i) {
    if (rejected[i]) continue;
    BundleObservation o = c.problem.observations[i];
    Eigen::Vector2d uv;
    // The reference clock offset is part of the truth: the camera saw the lamp at stamp − δ.
    if (!project(c.reference.camera, observed_world_point(o, c.reference.clock_offset_s), &uv)) continue;
    o.pixel = uv;
    // A zero covariance (exact point) has no Cholesky factor; LDLᵀ handles semi-definite ones.
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(o.world_cov);
    Eigen::Matrix3d L = ldlt.matrixL();
    L = ldlt.transpositionsP().transpose() * L;
    const Eigen::Vector3d d = ldlt.vectorD().cwiseMax(0.0).cwiseSqrt();
    const double time = c.epoch_time_s.empty() ? o.time_s : c.epoch_time_s[i];
    t.world_factor.push_back(scaled && std::isfinite(time) ? Eigen::Matrix3d(S * L * d.asDiagonal())
                                                           : Eigen::Matrix3d(L * d.asDiagonal()));
    t.pixel_sigma.push_back(o.pixel_sigma_px > 0 ? o.pixel_sigma_px : c.problem.pixel_sigma_px);
    t.key.push_back(shared && !c.world_noise_key.empty() ? c.world_noise_key[i] : -1);
    t.time_s.push_back(time);
    t.index.push_back(i);
    t.observations.push_back(o);
  }
  if (t.observations.size() < 6)
    throw_calibration_error("montecarlo " + c.problem.camera_id,
                            "only " + std::to_string(t.observations.size()) +
                                " points project through the reference camera; nothing to simulate");
  return t;
}

/// Where each simulated PPK fix sits on a Gauss–Markov chain (MonteCarloOptions::ppk_error):
/// chain 0 holds the epochs the cameras share by world-noise key (one node per key), chain 1 + c
/// camera c's unkeyed fixes (one node each); a chain's nodes in time order.
struct GaussMarkovChains {
  std::vector<std::vector<double>> t_s;  ///< per chain, its nodes' times (ascending)
  /// Per camera and kept observation: {chain, node}; chain −1 off every chain (no GM part).
  std::vector<std::vector<std::pair<int, std::size_t>>> node;
};

GaussMarkovChains gauss_markov_chains(const std::vector<CameraTruth>& truth, const PpkErrorModel& model) {
  GaussMarkovChains g;
  g.t_s.resize(truth.size() + 1);
  std::map<std::int64_t, double> key_time;  // a key's epoch: the time of its first fix
  for (std::size_t c = 0; c < truth.size(); ++c) {
    g.node.emplace_back(truth[c].observations.size(), std::make_pair(-1, std::size_t{0}));
    if (!model.correlated()) continue;
    for (std::size_t i = 0; i < truth[c].observations.size(); ++i)
      if (truth[c].key[i] >= 0 && std::isfinite(truth[c].time_s[i]))
        key_time.emplace(truth[c].key[i], truth[c].time_s[i]);
  }
  if (!model.correlated()) return g;
  // Ties in time keep key order (and observation order below): the same chain on every platform.
  std::vector<std::pair<double, std::int64_t>> keys;
  for (const auto& [k, t] : key_time) keys.emplace_back(t, k);
  std::sort(keys.begin(), keys.end());
  std::map<std::int64_t, std::size_t> node_of_key;
  for (const auto& [t, k] : keys) node_of_key[k] = g.t_s[0].size(), g.t_s[0].push_back(t);
  for (std::size_t c = 0; c < truth.size(); ++c) {
    const CameraTruth& tr = truth[c];
    std::vector<std::pair<double, std::size_t>> own;
    for (std::size_t i = 0; i < tr.observations.size(); ++i) {
      if (!std::isfinite(tr.time_s[i])) continue;
      if (tr.key[i] >= 0)
        g.node[c][i] = {0, node_of_key.at(tr.key[i])};
      else
        own.emplace_back(tr.time_s[i], i);
    }
    std::sort(own.begin(), own.end());
    const int chain = static_cast<int>(c) + 1;
    for (const auto& [t, i] : own) g.node[c][i] = {chain, g.t_s[c + 1].size()}, g.t_s[c + 1].push_back(t);
  }
  return g;
}

/// Trial `trial`'s Gauss–Markov part of every camera's kept observations (zero off the chains): each
/// chain drawn by the exact discretisation (pipeline/simulate/ppk_error.hpp draw_gauss_markov).
/// Empty per camera when the model has no GM part.
std::vector<std::vector<Eigen::Vector3d>> trial_gauss_markov(const GaussMarkovChains& g,
                                                             const PpkErrorModel& model, std::uint64_t seed,
                                                             std::size_t trial) {
  std::vector<std::vector<Eigen::Vector3d>> out(g.node.size());
  if (!model.correlated()) return out;
  std::vector<std::vector<Eigen::Vector3d>> chain(g.t_s.size());
  for (std::size_t k = 0; k < g.t_s.size(); ++k)
    chain[k] =
        draw_gauss_markov(model.gm_sd(), model.tau(), g.t_s[k], mix_seed(seed, kGaussMarkovStream, trial, k));
  for (std::size_t c = 0; c < g.node.size(); ++c)
    for (const auto& [k, j] : g.node[c])
      out[c].push_back(k >= 0 ? chain[static_cast<std::size_t>(k)][j] : Eigen::Vector3d::Zero());
  return out;
}

/// One trial's problem: truth + noise, priors re-drawn about the reference values (a prior is a
/// measurement too, so the covariance it enters assumes it scatters by its σ).
CalibrationProblem trial_problem(const MonteCarloCamera& c, const CameraTruth& t, const MonteCarloOptions& o,
                                 std::size_t trial, const std::vector<Eigen::Vector3d>& gauss_markov,
                                 DeterministicRandom& rng) {
  CalibrationProblem p = c.problem;
  p.observations = t.observations;
  for (std::size_t i = 0; i < p.observations.size(); ++i) {
    BundleObservation& ob = p.observations[i];
    if (o.world_noise) {
      const double a = rng.normal(), b = rng.normal(), d = rng.normal();  // drawn always: streams aligned
      const Eigen::Vector3d z =
          t.key[i] >= 0 ? keyed_normal3(o.seed, trial, t.key[i]) : Eigen::Vector3d(a, b, d);
      ob.world += t.world_factor[i] * z;
      if (!gauss_markov.empty()) ob.world += gauss_markov[i];
    }
    if (o.image_noise) {
      const double zu = rng.normal(), zv = rng.normal();
      ob.pixel += t.pixel_sigma[i] * Eigen::Vector2d(zu, zv);
    }
  }
  const Camera& ref = c.reference.camera;
  const std::vector<CameraParameter> free = expand_free_parameters(p.free);
  if (p.priors.principal_point_px &&
      (contains(free, CameraParameter::u0) || contains(free, CameraParameter::v0))) {
    const double zu = rng.normal(), zv = rng.normal();
    p.priors.principal_point_px = Eigen::Vector2d(ref.intr.u0_px, ref.intr.v0_px) +
                                  p.priors.principal_point_sigma_px * Eigen::Vector2d(zu, zv);
  }
  if (p.priors.center_enu_m && contains(free, CameraParameter::CE)) {
    const double a = rng.normal(), b = rng.normal(), d = rng.normal();  // in this order on every compiler
    const Eigen::Vector3d z(a, b, d);
    p.priors.center_enu_m = ref.pose.center() + p.priors.center_sigma_m * z;
  }
  return p;
}

/// What a trial keeps of a calibration: the camera and its clock offset.
struct TrialCamera {
  Camera camera;
  double clock_offset_s = 0;
  double value(const Camera& reference, CameraParameter p) const {
    return parameter_value(camera, p, reference, clock_offset_s);
  }
};

struct TrialOutcome {
  std::vector<std::optional<TrialCamera>> cameras;  ///< per camera; empty when the calibration failed
  std::vector<std::string> failure;
  std::vector<std::optional<Eigen::Vector3d>> pole_error;  ///< triangulated − truth, per pole
};

/// The network of one trial (docs/optimisation.md "Network bundle"): the cameras' trial problems
/// joined through their world-noise keys — observations with the same key ≥ 0 are one GNSS epoch
/// (or control pole), one point whose prior is the first such observation's noisy world point and
/// which the others see displaced by the difference of their true world points (the lamp's motion
/// between the cameras' frames); a negative key is a point of its own. Started at the reference
/// cameras, as the calibrate stage starts at the per-camera results.
NetworkProblem trial_network(const std::vector<const MonteCarloCamera*>& cams,
                             const std::vector<const CameraTruth*>& truth,
                             const std::vector<CalibrationProblem>& problems) {
  NetworkProblem n;
  std::map<std::int64_t, std::pair<std::size_t, Eigen::Vector3d>> point_of_key;  // → point, true world
  for (std::size_t c = 0; c < cams.size(); ++c) {
    const CalibrationProblem& p = problems[c];
    n.cameras.push_back(network_camera(p, cams[c]->reference.camera, cams[c]->reference.clock_offset_s));
    for (std::size_t i = 0; i < p.observations.size(); ++i) {
      const BundleObservation& o = p.observations[i];
      const Eigen::Vector3d& truth_world = truth[c]->observations[i].world;
      NetworkObservation ob;
      ob.camera = c, ob.pixel = o.pixel, ob.pixel_sigma_px = o.pixel_sigma_px, ob.velocity = o.velocity;
      ob.source = p.camera_id + " " + o.source;
      const std::int64_t key = truth[c]->key[i];
      auto it = key >= 0 ? point_of_key.find(key) : point_of_key.end();
      if (it == point_of_key.end()) {
        NetworkPoint pt;
        pt.prior_enu = o.world;
        pt.prior_cov = o.world_cov;
        // The epoch's place in the chain the trial network weighs it by (NetworkOptions::ppk_error).
        pt.time_s = truth[c]->time_s[i];
        pt.source = ob.source;
        if (key >= 0) it = point_of_key.emplace(key, std::make_pair(n.points.size(), truth_world)).first;
        ob.point = n.points.size();
        n.points.push_back(pt);
      } else {
        ob.point = it->second.first;
        ob.offset_m = truth_world - it->second.second;
      }
      n.observations.push_back(ob);
    }
  }
  return n;
}

void check_monte_carlo_inputs(const std::vector<MonteCarloCamera>& cameras,
                              const std::vector<MonteCarloPole>& poles, const MonteCarloOptions& options) {
  if (options.trials < 1)
    throw_config_error("", "trials", "must be at least 1, got " + std::to_string(options.trials));
  for (const MonteCarloPole& pole : poles)
    for (std::size_t c : pole.cameras)
      if (c >= cameras.size())
        throw_config_error("", "poles",
                           "pole " + pole.id + " names camera index " + std::to_string(c) + " of " +
                               std::to_string(cameras.size()));
}

/// The cameras calibrated by the network: re-run as one network per trial when there are two or
/// more of them; a network camera alone is its own bundle (calibrate_camera "network").
struct NetworkMembers {
  std::vector<std::size_t> index;
  std::vector<const MonteCarloCamera*> cams;
  std::vector<const CameraTruth*> truth;
};

NetworkMembers network_members(const std::vector<MonteCarloCamera>& cameras,
                               const std::vector<CameraTruth>& truth) {
  NetworkMembers m;
  for (std::size_t c = 0; c < cameras.size(); ++c)
    if (truth[c].method == "network")
      m.index.push_back(c), m.cams.push_back(&cameras[c]), m.truth.push_back(&truth[c]);
  return m;
}

/// What every trial reads.
struct TrialInputs {
  const std::vector<MonteCarloCamera>& cameras;
  const std::vector<CameraTruth>& truth;
  const GaussMarkovChains& chains;
  const NetworkMembers& network;
  const std::vector<MonteCarloPole>& poles;
  const MonteCarloOptions& options;
  const CrossCovariances* reference_cross;  ///< the joint covariance's cross blocks (null: none)
};

/// The cross blocks between the views' cameras `used` (indices into the reference's), as
/// triangulate_point takes them for views in that order: a block that does not fit the two views'
/// calibrations (one without a usable covariance, a table of another size) is left out, those
/// cameras taken as independent, as the intersect stage does. Empty without a reference.
CrossCovariances cross_of(const CrossCovariances* reference_cross, const std::vector<std::size_t>& used,
                          const std::vector<TriangulationView>& views) {
  CrossCovariances cross;
  if (!reference_cross || reference_cross->empty()) return cross;
  cross.assign(used.size(), std::vector<Eigen::MatrixXd>(used.size()));
  for (std::size_t i = 0; i < used.size(); ++i)
    for (std::size_t j = 0; j < used.size(); ++j) {
      if (i == j || used[i] >= reference_cross->size() || used[j] >= (*reference_cross)[used[i]].size())
        continue;
      const Eigen::MatrixXd& m = (*reference_cross)[used[i]][used[j]];
      if (m.rows() == static_cast<Eigen::Index>(views[i].calibration.parameters.size()) &&
          m.cols() == static_cast<Eigen::Index>(views[j].calibration.parameters.size()))
        cross[i][j] = m;
    }
  return cross;
}

/// A view of a pole at `uv` through `camera`, weighed as the intersect stage weighs it: the pick σ
/// and the reference calibration's covariance (none when it has no usable one: taken as exact).
TriangulationView pole_view(const Camera& camera, const Eigen::Vector2d& uv,
                            const MonteCarloCamera& reference, const MonteCarloOptions& options) {
  TriangulationView v;
  v.camera = camera;
  v.uv_px = uv;
  v.calibration = camera_covariance(reference.reference);
  v.pick_sigma_px = options.pick_sigma_px;
  return v;
}

/// Trial t's calibrations: every camera from its own noisy problem, the network's cameras adjusted
/// together. A calibration error is the trial's failure for that camera; any other error stops.
void calibrate_trial(const TrialInputs& in, std::size_t t, TrialOutcome* out) {
  const std::size_t n_cameras = in.cameras.size();
  out->cameras.resize(n_cameras);
  out->failure.resize(n_cameras);
  std::vector<CalibrationProblem> joint;  // the network's cameras, adjusted together below
  const std::vector<std::vector<Eigen::Vector3d>> gm =
      trial_gauss_markov(in.chains, in.options.ppk_error, in.options.seed, t);
  for (std::size_t c = 0; c < n_cameras; ++c) {
    DeterministicRandom rng(mix_seed(in.options.seed, c, t));
    CalibrationProblem p = trial_problem(in.cameras[c], in.truth[c], in.options, t, gm[c], rng);
    if (in.network.index.size() >= 2 && in.truth[c].method == "network") {
      joint.push_back(std::move(p));
      continue;
    }
    try {
      const CalibrationResult r = calibrate_camera(in.truth[c].method, p);
      out->cameras[c] = TrialCamera{r.camera, r.clock_offset_s};
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::calibration) throw;
      out->failure[c] = e.what();
    }
  }
  if (joint.empty()) return;
  try {
    const NetworkProblem n = trial_network(in.network.cams, in.network.truth, joint);
    NetworkOptions options;
    options.ppk_error = in.options.ppk_error;  // weighed as the reference network was
    const NetworkResult r = network_adjust(n.cameras, n.points, n.observations, options);
    for (std::size_t j = 0; j < in.network.index.size(); ++j)
      out->cameras[in.network.index[j]] =
          TrialCamera{r.cameras[j].calibration.camera, r.cameras[j].calibration.clock_offset_s};
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::calibration) throw;
    for (std::size_t c : in.network.index) out->failure[c] = e.what();
  }
}

/// Trial t's pole errors: every pole picked with noise in the cameras that see it and
/// triangulated with the trial's cameras, weighed as the intersect stage weighs the run's (none
/// when fewer than two calibrated cameras see it).
void triangulate_trial_poles(const TrialInputs& in, std::size_t t, TrialOutcome* out) {
  DeterministicRandom rng(mix_seed(in.options.seed, kPoleStream, t));
  for (const MonteCarloPole& pole : in.poles) {
    std::vector<TriangulationView> views;
    std::vector<std::size_t> used;
    for (std::size_t c : pole.cameras) {
      Eigen::Vector2d uv;
      const bool ok = project(in.cameras[c].reference.camera, pole.enu, &uv);
      const double zu = rng.normal(), zv = rng.normal();  // drawn always: streams stay aligned
      if (!ok || !out->cameras[c]) continue;
      views.push_back(pole_view(out->cameras[c]->camera,
                                uv + in.options.pick_sigma_px * Eigen::Vector2d(zu, zv), in.cameras[c],
                                in.options));
      used.push_back(c);
    }
    std::optional<Eigen::Vector3d> err;
    if (views.size() >= 2) {
      try {
        const CrossCovariances cross = cross_of(in.reference_cross, used, views);
        err = triangulate_point(views, "pole " + pole.id, cross.empty() ? nullptr : &cross).point - pole.enu;
      } catch (const Error&) {
      }
    }
    out->pole_error.push_back(err);
  }
}

/// Camera c's statistics over the trials (in trial order: the same sums for any thread count).
CameraMonteCarlo camera_statistics(const MonteCarloCamera& camera, const CameraTruth& truth, std::size_t c,
                                   const std::vector<TrialOutcome>& outcome) {
  const CalibrationResult& ref = camera.reference;
  CameraMonteCarlo cm;
  cm.camera_id = camera.problem.camera_id;
  cm.method = truth.method;
  for (const TrialOutcome& o : outcome) {
    if (o.cameras[c]) {
      ++cm.trials_ok;
    } else {
      ++cm.trials_failed;
      if (cm.first_failure.empty()) cm.first_failure = o.failure[c];
    }
  }
  if (cm.trials_ok == 0)
    throw_calibration_error("montecarlo " + cm.camera_id,
                            "every trial failed; the first: " + cm.first_failure);
  for (const CameraParameter name : truth.parameters) {
    ParameterStatistics s;
    s.parameter = name;
    s.estimate = parameter_value(ref.camera, name, ref.camera, ref.clock_offset_s);
    double sum = 0;
    for (const TrialOutcome& o : outcome)
      if (o.cameras[c]) sum += o.cameras[c]->value(ref.camera, name);
    s.mean = sum / cm.trials_ok;
    double ss = 0;
    for (const TrialOutcome& o : outcome)
      if (o.cameras[c]) {
        const double d = o.cameras[c]->value(ref.camera, name) - s.mean;
        ss += d * d;
      }
    s.bias_mc = s.mean - s.estimate;
    s.sd_mc = cm.trials_ok > 1 ? std::sqrt(ss / (cm.trials_ok - 1)) : kNaN;
    s.sd_predicted = ref.sigma(name);
    cm.parameters.push_back(s);
  }
  return cm;
}

/// A pole's predicted 1σ: exact picks through the reference cameras with their covariances, and
/// the cross blocks of a joint (network) covariance when given. NaN when it cannot be triangulated.
double predicted_pole_sigma(const MonteCarloPole& pole, const std::vector<MonteCarloCamera>& cameras,
                            const MonteCarloOptions& options, const CrossCovariances* reference_cross) {
  std::vector<TriangulationView> views;
  std::vector<std::size_t> used;
  for (std::size_t c : pole.cameras) {
    Eigen::Vector2d uv;
    if (!project(cameras[c].reference.camera, pole.enu, &uv)) continue;
    views.push_back(pole_view(cameras[c].reference.camera, uv, cameras[c], options));
    used.push_back(c);
  }
  const CrossCovariances cross = cross_of(reference_cross, used, views);
  double sigma = kNaN;
  if (views.size() >= 2) {
    try {
      sigma = triangulate_point(views, "pole " + pole.id, cross.empty() ? nullptr : &cross).sigma_m;
    } catch (const Error&) {
    }
  }
  return sigma;
}

/// Pole k's errors over the trials (in trial order).
PoleMonteCarlo pole_statistics(const MonteCarloPole& pole, std::size_t k,
                               const std::vector<TrialOutcome>& outcome) {
  PoleMonteCarlo pm;
  pm.id = pole.id;
  double ss = 0, sn = 0;
  for (const TrialOutcome& o : outcome) {
    if (!o.pole_error[k]) continue;
    const Eigen::Vector3d& e = *o.pole_error[k];
    ++pm.n;
    pm.mean_error_m += e;
    ss += e.squaredNorm();
    sn += e.norm();
    pm.max_error_m = std::max(pm.max_error_m, e.norm());
  }
  if (pm.n > 0) {
    pm.mean_error_m /= pm.n;
    pm.rms_error_m = std::sqrt(ss / pm.n);
    pm.mean_error_norm_m = sn / pm.n;
  } else {
    pm.mean_error_m.setConstant(kNaN);
    pm.rms_error_m = pm.mean_error_norm_m = pm.max_error_m = kNaN;
  }
  return pm;
}

}  // namespace

MonteCarloResult run_monte_carlo(const std::vector<MonteCarloCamera>& cameras,
                                 const std::vector<MonteCarloPole>& poles, const MonteCarloOptions& options,
                                 const CrossCovariances* reference_cross) {
  check_monte_carlo_inputs(cameras, poles, options);
  std::vector<CameraTruth> truth;
  for (const MonteCarloCamera& c : cameras)
    truth.push_back(make_truth(c, options.shared_world_noise, options.ppk_error));
  const GaussMarkovChains chains = gauss_markov_chains(truth, options.ppk_error);
  const NetworkMembers network = network_members(cameras, truth);
  const TrialInputs in{cameras, truth, chains, network, poles, options, reference_cross};

  const std::size_t nt = static_cast<std::size_t>(options.trials);
  std::vector<TrialOutcome> outcome(nt);
  auto run_trial = [&](std::size_t t) {
    calibrate_trial(in, t, &outcome[t]);
    triangulate_trial_poles(in, t, &outcome[t]);
  };
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nt, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t t = r.begin(); t != r.end(); ++t) run_trial(t);
                      });
  });

  // Statistics in trial order: the same sums in the same order for any thread count.
  MonteCarloResult result;
  result.trials = options.trials;
  for (std::size_t c = 0; c < cameras.size(); ++c)
    result.cameras.push_back(camera_statistics(cameras[c], truth[c], c, outcome));
  for (std::size_t k = 0; k < poles.size(); ++k) {
    PoleMonteCarlo pm = pole_statistics(poles[k], k, outcome);
    pm.sigma_predicted_m = predicted_pole_sigma(poles[k], cameras, options, reference_cross);
    result.poles.push_back(pm);
  }
  return result;
}

std::vector<std::vector<Eigen::Vector3d>> monte_carlo_world_noise(
    const std::vector<MonteCarloCamera>& cameras, const MonteCarloOptions& options, std::size_t trial) {
  std::vector<CameraTruth> truth;
  for (const MonteCarloCamera& c : cameras)
    truth.push_back(make_truth(c, options.shared_world_noise, options.ppk_error));
  const std::vector<std::vector<Eigen::Vector3d>> gm = trial_gauss_markov(
      gauss_markov_chains(truth, options.ppk_error), options.ppk_error, options.seed, trial);
  std::vector<std::vector<Eigen::Vector3d>> out;
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    // The trial's own draw (calibrate_trial's generator), less the truth.
    DeterministicRandom rng(mix_seed(options.seed, c, trial));
    const CalibrationProblem p = trial_problem(cameras[c], truth[c], options, trial, gm[c], rng);
    out.emplace_back(cameras[c].problem.observations.size(), Eigen::Vector3d::Constant(kNaN));
    for (std::size_t i = 0; i < p.observations.size(); ++i)
      out[c][truth[c].index[i]] = p.observations[i].world - truth[c].observations[i].world;
  }
  return out;
}

std::string format_montecarlo_csv(const MonteCarloResult& r) {
  std::string s = "camera,parameter,estimate,bias_mc,sd_mc,sd_predicted\n";
  for (const CameraMonteCarlo& c : r.cameras)
    for (const ParameterStatistics& p : c.parameters)
      s += c.camera_id + "," + parameter_name(p.parameter) + "," + format_finite("%.10g", p.estimate) + "," +
           format_finite("%.10g", p.bias_mc) + "," + format_finite("%.10g", p.sd_mc) + "," +
           format_finite("%.10g", p.sd_predicted) + "\n";
  return s;
}

std::string format_montecarlo_table(const CameraMonteCarlo& c) {
  char line[256];
  std::string s;
  std::snprintf(line, sizeof line, "camera %s (%s): %d trials, %d failed\n", c.camera_id.c_str(),
                c.method.c_str(), c.trials_ok + c.trials_failed, c.trials_failed);
  s += line;
  std::snprintf(line, sizeof line, "  %-9s %16s %13s %13s %13s %7s\n", "parameter", "estimate", "bias MC",
                "sd MC", "sd predicted", "ratio");
  s += line;
  for (const ParameterStatistics& p : c.parameters) {
    const double ratio = p.sd_mc / p.sd_predicted;
    std::snprintf(line, sizeof line, "  %-9s %16.9g %13.4g %13.4g %13s %7s\n", parameter_name(p.parameter),
                  p.estimate, p.bias_mc, p.sd_mc,
                  std::isfinite(p.sd_predicted) ? format_finite("%.4g", p.sd_predicted).c_str() : "-",
                  std::isfinite(ratio) ? format_finite("%.3f", ratio).c_str() : "-");
    s += line;
  }
  return s;
}

std::string format_montecarlo_pole_table(const std::vector<PoleMonteCarlo>& poles) {
  char line[256];
  std::string s = "intersection at the check poles (m):\n";
  std::snprintf(line, sizeof line, "  %-8s %5s %9s %9s %9s %10s %10s %10s\n", "pole", "n", "mean dE",
                "mean dN", "mean dU", "mean |dR|", "RMS |dR|", "pred. 1σ");
  s += line;
  for (const PoleMonteCarlo& p : poles) {
    std::snprintf(line, sizeof line, "  %-8s %5d %9.4f %9.4f %9.4f %10.4f %10.4f %10.4f\n", p.id.c_str(), p.n,
                  p.mean_error_m.x(), p.mean_error_m.y(), p.mean_error_m.z(), p.mean_error_norm_m,
                  p.rms_error_m, p.sigma_predicted_m);
    s += line;
  }
  return s;
}

}  // namespace rangecal
