#include "pipeline/steps/calibration_methods.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "config/error.hpp"
#include "optim/bundle/bundle_adjustment.hpp"
#include "optim/estimation/reprojection_stats.hpp"
#include "optim/estimation/symmetric_part.hpp"
#include "optim/methods/dlt_lmqn.hpp"
#include "optim/methods/tsai_sassa.hpp"
#include "optim/network/network_adjustment.hpp"
#include "pipeline/io/method_details_json.hpp"
#include "pipeline/steps/network_problem.hpp"
#include "vision/calibration/dlt.hpp"
#include "vision/calibration/tsai.hpp"

namespace rangecal {
namespace {

constexpr double kNotMeasured = std::numeric_limits<double>::quiet_NaN();

std::vector<PointCorrespondence> to_points(const std::vector<BundleObservation>& obs) {
  std::vector<PointCorrespondence> pts;
  pts.reserve(obs.size());
  for (const auto& o : obs) pts.push_back({o.world, o.pixel});
  return pts;
}

/// Principal point used when it is not estimated: the prior, else the image centre (docs/optimisation.md).
Eigen::Vector2d default_principal_point(const CalibrationProblem& p) {
  if (p.priors.principal_point_px) return *p.priors.principal_point_px;
  return {p.sensor.center_u_px(), p.sensor.center_v_px()};
}

/// The result of `method`: the camera named as the problem's, its reprojection over the points
/// not rejected.
CalibrationResult finish(const std::string& method, const CalibrationProblem& p, Camera cam,
                         std::vector<std::size_t> rejected) {
  CalibrationResult r;
  cam.id = p.camera_id;
  r.camera_id = p.camera_id;
  r.method = method;
  r.camera = cam;
  r.rejected = std::move(rejected);
  r.reprojection = reprojection_stats(reprojection_residuals(cam, p.observations), r.rejected);
  return r;
}

TsaiSensor tsai_sensor(const CalibrationProblem& p) {
  TsaiSensor s;
  s.width_px = p.sensor.width_px;
  s.height_px = p.sensor.height_px;
  s.dx_mm = p.sensor.dx_mm;
  s.dy_mm = p.sensor.dy_mm;
  const Eigen::Vector2d pp = default_principal_point(p);
  s.u0_px = pp.x();
  s.v0_px = pp.y();
  return s;
}

// ---------------------------------------------------------------------------------------------
// The methods.

// Where Tsai's linear f, Tz step is ill-conditioned, step 2 starts from the lens's nominal focal
// length (vision/calibration/tsai.hpp tsai_f_tz_start).
CalibrationRun run_tsai(const CalibrationProblem& p) {
  TsaiOptions o;
  o.nominal_f_mm = p.nominal_focal_mm;
  const TsaiResult t = tsai_calibrate(to_points(p.observations), tsai_sensor(p), o);
  CalibrationResult r = finish("tsai", p, t.camera, {});
  r.details = tsai_details_json(t);
  std::vector<CalibrationWarning> warnings;
  if (!t.fallback.empty())
    warnings.push_back({CalibrationWarningKind::projection_fallback, {}, "tsai: " + t.fallback});
  return {r, warnings};
}

// seed 002 §3.2.3: Tsai step 1, then f, Tz, k1 by SA-sparrow search, finished by an LM polish
// that the result records. The search seed is the mission's seed; the search starts from the lens's
// nominal focal length where Tsai's linear f, Tz step is ill-conditioned.
CalibrationRun run_tsai_sassa(const CalibrationProblem& p) {
  TsaiSassaOptions o;
  o.search.seed = p.seed;
  o.nominal_f_mm = p.nominal_focal_mm;
  const TsaiSassaResult t = tsai_sassa_calibrate(to_points(p.observations), tsai_sensor(p), o);
  CalibrationResult r = finish("tsai_sassa", p, t.camera, {});
  r.details = tsai_sassa_details_json(t, o);
  return {r, t.warnings};
}

CalibrationRun run_dlt_lmqn(const CalibrationProblem& p) {
  DltLmqnOptions o;
  o.free = expand_free_parameters(p.free);
  o.fixed_principal_point_px = default_principal_point(p);
  o.pixel_sigma_px = p.pixel_sigma_px;
  o.seed = p.seed;
  const DltLmqnResult d = dlt_lmqn_calibrate(p.observations, p.sensor, o);
  CalibrationRun run{finish("dlt_lmqn", p, d.camera, d.rejected), {}};
  CalibrationResult& r = run.result;
  if (d.covariance.size() > 0) {
    r.covariance = d.covariance;
    r.parameters = d.parameters;
    const int ce = r.parameter_index(CameraParameter::CE);
    if (ce >= 0) r.center_covariance_m2 = r.covariance.block<3, 3>(ce, ce);
  } else {
    run.warnings.push_back({CalibrationWarningKind::no_covariance,
                            {},
                            "dlt_lmqn: the free parameters are not all determined by this geometry "
                            "(normal matrix rank-deficient); no covariance"});
  }
  r.details = dlt_lmqn_details_json(d);
  return run;
}

CalibrationRun run_bundle(const CalibrationProblem& p) {
  const std::vector<CameraParameter> free = expand_free_parameters(p.free);
  Camera start;
  std::string start_method = "tsai";
  bool from_tsai = false;
  try {
    const TsaiResult t = tsai_calibrate(to_points(p.observations), tsai_sensor(p));
    // Tsai's own fallbacks (a start off the f–distance ridge, k1 dropped) keep Tsai from failing,
    // but a camera that needed them is a poor start for the bundle: DLT's then.
    from_tsai = t.start.source == TsaiStartSource::linear && t.fallback.empty();
    start = t.camera;
    start.id = p.camera_id;
  } catch (const Error&) {
    from_tsai = false;
  }
  if (!from_tsai) {
    // Tsai needs its radial alignment constraint to hold; DLT has no such need.
    DltOptions o;
    o.seed = p.seed;
    start = dlt_calibrate(to_points(p.observations), p.sensor, o).camera;
    start_method = "dlt";
  }
  start.intr.width_px = p.sensor.width_px;
  start.intr.height_px = p.sensor.height_px;
  start.intr.dx_mm = p.sensor.dx_mm;
  start.intr.dy_mm = p.sensor.dy_mm;
  hold_fixed_intrinsics(free, default_principal_point(p), &start.intr);
  const BundleResult b = bundle_adjust(start, p.observations, bundle_options(p));
  CalibrationResult r = b.calibration;
  r.camera.id = p.camera_id;
  r.camera_id = p.camera_id;
  r.details = bundle_details_json(b.details);
  r.details["start"] = start_method;
  return {r, b.warnings};
}

// One camera alone in the network: every pair its own point under its PPK prior, started from the
// per-camera bundle — the same estimator (docs/optimisation.md "Network bundle"); the calibrate
// stage joins the cameras through their shared epochs instead (network_problem.hpp).
CalibrationRun run_network_one_camera(const CalibrationProblem& p) {
  const CalibrationResult start = run_bundle(p).result;
  const std::vector<Correspondence> pairs(p.observations.size() - p.control_pole_ids.size());
  NetworkCameraInput in{&p, &pairs, start.camera, start.clock_offset_s};
  const NetworkProblem n = make_network_problem({in}, LampTrack{}, 0);
  const NetworkResult r = network_adjust(n.cameras, n.points, n.observations);
  CalibrationResult out = r.cameras[0].calibration;
  out.camera.id = p.camera_id;
  out.camera_id = p.camera_id;
  out.details = bundle_details_json(r.cameras[0].details);
  return {out, r.cameras[0].warnings};
}

// A lamp track whose points lie in one plane (e.g. every ascent at the same depth) leaves f and the
// distance along the optical axis inseparable for every method here: DLT and Tsai need
// non-coplanar points and the bundle would start from nothing. The initialisers test exact
// coplanarity; with PPK noise a flat track is only coplanar to within the noise, so the test here
// compares the points' RMS distance from their best-fit plane with their own 1σ.
void require_depth_beyond_noise(const std::string& method, const CalibrationProblem& p) {
  const std::size_t n = p.observations.size();
  if (n < 4) return;  // the methods' own point-count checks give the better message
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  double var_sum = 0;
  for (const auto& o : p.observations) {
    mean += o.world;
    var_sum += o.world_cov.trace() / 3.0;
  }
  mean /= static_cast<double>(n);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& o : p.observations) scatter += (o.world - mean) * (o.world - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(scatter / static_cast<double>(n));
  if (!es.eigenvalues().allFinite()) return;  // NaN input: the methods name the bad point
  const double thickness_m = std::sqrt(std::max(0.0, es.eigenvalues()[0]));
  const double extent_m = std::sqrt(std::max(0.0, es.eigenvalues()[2]));
  const double sigma_m = std::sqrt(var_sum / static_cast<double>(n));
  if (thickness_m > std::max(3.0 * sigma_m, 1e-6 * extent_m)) return;
  const Eigen::Vector3d normal = es.eigenvectors().col(0);
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "the %zu world points lie in one plane (RMS distance from it %.4f m, within 3x their 1 sigma "
                "%.4f m; plane normal E %.3f N %.3f U %.3f): focal length and depth cannot be separated — "
                "fly routes at different distances from the camera",
                n, thickness_m, sigma_m, normal.x(), normal.y(), normal.z());
  throw_calibration_error(p.camera_id.empty() ? method : p.camera_id + " " + method, buf);
}

/// A method's function; nullptr: known, but not a method for a lamp track.
using MethodFunction = CalibrationRun (*)(const CalibrationProblem&);

/// The method table: row i runs kCalibrationMethodNames[i] (pipeline/mission/calibration_method_names.hpp).
constexpr std::array<MethodFunction, kCalibrationMethodNames.size()> kMethodFunctions = {
    run_tsai, run_tsai_sassa, run_dlt_lmqn, run_bundle, run_network_one_camera, nullptr /* planar */,
};

}  // namespace

std::vector<Eigen::Vector2d> reprojection_residuals(const Camera& cam,
                                                    const std::vector<BundleObservation>& obs,
                                                    double clock_offset_s) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(obs.size());
  for (const auto& o : obs) {
    Eigen::Vector2d uv;
    out.push_back(project(cam, observed_world_point(o, clock_offset_s), &uv)
                      ? Eigen::Vector2d(uv - o.pixel)
                      : Eigen::Vector2d(kNotMeasured, kNotMeasured));
  }
  return out;
}

ReprojectionStats reprojection_stats(const std::vector<Eigen::Vector2d>& residuals,
                                     const std::vector<std::size_t>& rejected) {
  std::vector<char> used(residuals.size(), 1);
  for (std::size_t i : rejected)
    if (i < used.size()) used[i] = 0;
  ReprojectionStats s = reprojection_stats(residuals, used);
  s.n_rejected = static_cast<int>(rejected.size());
  return s;
}

CalibrationRun run_calibration_method(const std::string& method, const CalibrationProblem& problem) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto name = std::find(kCalibrationMethodNames.begin(), kCalibrationMethodNames.end(), method);
  if (name == kCalibrationMethodNames.end())
    throw Error(ErrorKind::usage, "", 0, "calibrate.method", "unknown method '" + method + "'");
  const MethodFunction run =
      kMethodFunctions[static_cast<std::size_t>(name - kCalibrationMethodNames.begin())];
  if (!run)
    throw Error(ErrorKind::usage, "", 0, "calibrate.method",
                "'planar' calibrates from several views of a planar target (seed 001); a lamp track is one "
                "view of non-coplanar points — use bundle, tsai, tsai_sassa or dlt_lmqn");
  require_depth_beyond_noise(method, problem);
  CalibrationRun out = run(problem);
  CalibrationResult& r = out.result;
  if (method != "bundle" && method != "network" &&
      contains(expand_free_parameters(problem.free), CameraParameter::clock_offset))
    out.warnings.push_back({CalibrationWarningKind::clock_offset_not_estimated,
                            {CameraParameter::clock_offset},
                            "clock_offset is estimated by the bundle method only; " + method +
                                " takes the frame time stamps as exact (clock offset 0)"});
  for (CalibrationWarning& w : out.warnings) w.camera = problem.camera_id;
  r.warnings = warning_texts(out.warnings);
  // Exact symmetry (round-off makes C and Cᵀ differ in the last bit; readers check symmetry).
  if (r.covariance.size() > 0) r.covariance = symmetric_part(r.covariance);
  r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

CalibrationResult calibrate_camera(const std::string& method, const CalibrationProblem& problem) {
  return run_calibration_method(method, problem).result;
}

}  // namespace rangecal
