#include "pipeline/steps/calibration_methods.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "config/error.hpp"
#include "optim/search/lm_qn.hpp"
#include "optim/search/tsai_sassa.hpp"
#include "vision/calibration/dlt.hpp"
#include "vision/calibration/linear_distortion.hpp"
#include "vision/calibration/tsai.hpp"

namespace rangecal {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool is_free(const CalibrationProblem& p, const std::string& name) {
  return std::find(p.free.begin(), p.free.end(), name) != p.free.end();
}
bool pose_free(const CalibrationProblem& p) {
  return is_free(p, "pose");
}

std::vector<PointCorrespondence> to_points(const std::vector<BundleObservation>& obs) {
  std::vector<PointCorrespondence> pts;
  pts.reserve(obs.size());
  for (const auto& o : obs) pts.push_back({o.world, o.pixel});
  return pts;
}

/// Principal point used when it is not estimated: the prior, else the image centre (SPEC §4.4).
Eigen::Vector2d default_principal_point(const CalibrationProblem& p) {
  if (p.priors.principal_point_px) return *p.priors.principal_point_px;
  return {p.sensor.center_u_px(), p.sensor.center_v_px()};
}

/// Puts the parameters that are not free at their default values (SPEC §4.4).
void reset_fixed_intrinsics(const CalibrationProblem& p, CameraIntrinsics* in) {
  in->width_px = p.sensor.width_px;
  in->height_px = p.sensor.height_px;
  in->dx_mm = p.sensor.dx_mm;
  in->dy_mm = p.sensor.dy_mm;
  const Eigen::Vector2d pp = default_principal_point(p);
  if (!is_free(p, "u0")) in->u0_px = pp.x();
  if (!is_free(p, "v0")) in->v0_px = pp.y();
  if (!is_free(p, "sx")) in->sx = 1.0;
  double* d[7] = {&in->dist.k1, &in->dist.k2, &in->dist.k3, &in->dist.p1,
                  &in->dist.p2, &in->dist.a1, &in->dist.a2};
  for (int k = 0; k < 7; ++k)
    if (!is_free(p, kDistortionNames[k])) *d[k] = 0;
}

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

// ---------------------------------------------------------------------------------------------
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

CalibrationResult run_tsai(const CalibrationProblem& p) {
  const TsaiResult t = tsai_calibrate(to_points(p.observations), tsai_sensor(p));
  CalibrationResult r = finish("tsai", p, t.camera, {});
  r.details = {{"f_linear_mm", t.f_linear_mm},
               {"Tz_linear_m", t.Tz_linear},
               {"step1_linear_rms_mm", t.step1.linear_rms_mm},
               {"step2_iterations", t.iterations},
               {"step2_converged", t.converged},
               {"rms_sensor_mm", t.rms_sensor_mm},
               {"covariance", "not computed (Tsai's method gives no uncertainty; see the bundle method)"}};
  return r;
}

// ---------------------------------------------------------------------------------------------
// seed 002 §3.2.3: Tsai step 1, then f, Tz, k1 by SA-sparrow search, finished by an LM polish
// that the result records (optim/search/tsai_sassa.hpp). The search seed is the mission's seed.
CalibrationResult run_tsai_sassa(const CalibrationProblem& p) {
  TsaiSassaOptions o;
  o.search.seed = p.seed;
  TsaiSassaResult t = tsai_sassa_calibrate(to_points(p.observations), tsai_sensor(p), o);
  CalibrationResult r = finish("tsai_sassa", p, t.camera, {});
  r.details = t.calibration.details;
  r.warnings = t.calibration.warnings;
  r.details["covariance"] = "not computed (the search gives no uncertainty; see the bundle method)";
  return r;
}

// ---------------------------------------------------------------------------------------------
CalibrationResult run_bundle(const CalibrationProblem& p) {
  Camera start;
  std::string start_method = "tsai";
  try {
    start = run_tsai(p).camera;
  } catch (const Error&) {
    // Tsai needs its radial alignment constraint to hold; DLT has no such need.
    DltOptions o;
    o.seed = p.seed;
    start = dlt_calibrate(to_points(p.observations), p.sensor, o).camera;
    start_method = "dlt";
  }
  reset_fixed_intrinsics(p, &start.intr);
  BundleOptions opt;
  opt.free = p.free;
  opt.pixel_sigma_px = p.pixel_sigma_px;
  if (p.priors.principal_point_px && (is_free(p, "u0") || is_free(p, "v0"))) {
    opt.priors.use_principal_point = true;
    opt.priors.principal_point_px = *p.priors.principal_point_px;
    opt.priors.principal_point_sigma_px = p.priors.principal_point_sigma_px;
  }
  if (p.priors.center_enu_m && pose_free(p)) {
    opt.priors.use_center = true;
    opt.priors.center_enu_m = *p.priors.center_enu_m;
    opt.priors.center_sigma_m = Eigen::Vector3d::Constant(p.priors.center_sigma_m);
  }
  BundleResult b = bundle_adjust(start, p.observations, opt);
  CalibrationResult r = b.calibration;
  r.camera.id = p.camera_id;
  r.camera_id = p.camera_id;
  r.method = "bundle";
  r.details["start"] = start_method;
  return r;
}

// ---------------------------------------------------------------------------------------------
// dlt_lmqn: the parameter vector and its scaling. LM's damping μI is not scale invariant, so the
// search runs in z = (x − x0)/scale with scales of each parameter's typical size.
struct ParamSpec {
  std::string name;
  double scale;
};

std::vector<ParamSpec> lmqn_parameters(const CalibrationProblem& p) {
  std::vector<ParamSpec> v;
  const std::pair<const char*, double> intr[] = {{"f", 1.0},   {"sx", 1e-3}, {"u0", 1.0},   {"v0", 1.0},
                                                 {"k1", 1e-5}, {"k2", 1e-8}, {"k3", 1e-11}, {"p1", 1e-5},
                                                 {"p2", 1e-5}, {"a1", 1e-4}, {"a2", 1e-4}};
  for (const auto& [n, s] : intr)
    if (is_free(p, n)) v.push_back({n, s});
  if (pose_free(p)) {
    for (const char* n : {"wx", "wy", "wz"}) v.push_back({n, 1e-4});
    for (const char* n : {"CE", "CN", "CU"}) v.push_back({n, 0.1});
  }
  return v;
}

/// The camera at parameter vector x (absolute values; rotation as a left perturbation of R0).
Camera camera_at(const Camera& base, const std::vector<ParamSpec>& spec, const Eigen::VectorXd& x) {
  Camera c = base;
  Eigen::Vector3d w = Eigen::Vector3d::Zero(), C = base.pose.center();
  for (std::size_t i = 0; i < spec.size(); ++i) {
    const std::string& n = spec[i].name;
    const double v = x[static_cast<Eigen::Index>(i)];
    if (n == "f")
      c.intr.f_mm = v;
    else if (n == "sx")
      c.intr.sx = v;
    else if (n == "u0")
      c.intr.u0_px = v;
    else if (n == "v0")
      c.intr.v0_px = v;
    else if (n == "k1")
      c.intr.dist.k1 = v;
    else if (n == "k2")
      c.intr.dist.k2 = v;
    else if (n == "k3")
      c.intr.dist.k3 = v;
    else if (n == "p1")
      c.intr.dist.p1 = v;
    else if (n == "p2")
      c.intr.dist.p2 = v;
    else if (n == "a1")
      c.intr.dist.a1 = v;
    else if (n == "a2")
      c.intr.dist.a2 = v;
    else if (n == "wx")
      w.x() = v;
    else if (n == "wy")
      w.y() = v;
    else if (n == "wz")
      w.z() = v;
    else if (n == "CE")
      C.x() = v;
    else if (n == "CN")
      C.y() = v;
    else if (n == "CU")
      C.z() = v;
  }
  const double a = w.norm();
  const Eigen::Matrix3d dR =
      a > 0 ? Eigen::AngleAxisd(a, w / a).toRotationMatrix() : Eigen::Matrix3d::Identity();
  c.pose.R = dR * base.pose.R;
  c.pose.T = -c.pose.R * C;
  return c;
}

Eigen::VectorXd values_of(const Camera& c, const std::vector<ParamSpec>& spec) {
  Eigen::VectorXd x(spec.size());
  const Eigen::Vector3d C = c.pose.center();
  for (std::size_t i = 0; i < spec.size(); ++i) {
    const std::string& n = spec[i].name;
    double v = 0;  // rotation perturbations start at 0
    if (n == "f")
      v = c.intr.f_mm;
    else if (n == "sx")
      v = c.intr.sx;
    else if (n == "u0")
      v = c.intr.u0_px;
    else if (n == "v0")
      v = c.intr.v0_px;
    else if (n == "k1")
      v = c.intr.dist.k1;
    else if (n == "k2")
      v = c.intr.dist.k2;
    else if (n == "k3")
      v = c.intr.dist.k3;
    else if (n == "p1")
      v = c.intr.dist.p1;
    else if (n == "p2")
      v = c.intr.dist.p2;
    else if (n == "a1")
      v = c.intr.dist.a1;
    else if (n == "a2")
      v = c.intr.dist.a2;
    else if (n == "CE")
      v = C.x();
    else if (n == "CN")
      v = C.y();
    else if (n == "CU")
      v = C.z();
    x[static_cast<Eigen::Index>(i)] = v;
  }
  return x;
}

CalibrationResult run_dlt_lmqn(const CalibrationProblem& p) {
  const auto pts = to_points(p.observations);
  DltOptions dopt;
  dopt.seed = p.seed;
  // The lamp's PPK noise alone projects to ~1 px at range (SPEC §8 demo): a 2 px gate would
  // reject good points, so RANSAC uses 4 px and the LM-QN stage weighs each point properly.
  dopt.inlier_threshold_px = 4.0;
  const DltResult dlt = dlt_calibrate(pts, p.sensor, dopt);
  Camera base = dlt.camera;
  reset_fixed_intrinsics(p, &base.intr);
  // Seed 000 eq. 8: linear least-squares initial values of the free distortion terms.
  DistortionTerms terms{};
  bool any_distortion = false;
  for (int k = 0; k < 7; ++k) any_distortion |= (terms[k] = is_free(p, kDistortionNames[k]));
  std::vector<PointCorrespondence> inliers;
  for (std::size_t i : dlt.inliers) inliers.push_back(pts[i]);
  if (any_distortion) base.intr.dist = fit_linear_distortion(base, inliers, terms).dist;

  // Whitening of each residual by its effective image covariance (as the bundle does).
  std::vector<Eigen::Matrix2d> W;
  for (const auto& o : p.observations) {
    const double s = o.pixel_sigma_px > 0 ? o.pixel_sigma_px : p.pixel_sigma_px;
    const Eigen::Matrix<double, 2, 3> J = pixel_jacobian_wrt_world(base, o.world);
    const Eigen::Matrix2d C = s * s * Eigen::Matrix2d::Identity() + J * o.world_cov * J.transpose();
    W.push_back(Eigen::Matrix2d(C.llt().matrixL()).inverse());
  }
  const std::vector<ParamSpec> spec = lmqn_parameters(p);
  const Eigen::Index n = static_cast<Eigen::Index>(spec.size());
  const Eigen::VectorXd x0 = values_of(base, spec);
  Eigen::VectorXd scale(n);
  for (Eigen::Index i = 0; i < n; ++i) scale[i] = spec[static_cast<std::size_t>(i)].scale;

  // RANSAC's gate works on the distortion-free DLT model; once LM-QN has fitted the distortion the
  // points are re-judged by their whitened residual (> 4σ after robust scaling → outlier) and the
  // fit repeated while the inlier set changes.
  std::vector<std::size_t> used = dlt.inliers;
  LmQnResult lm;
  Camera cam = base;
  for (int round = 0; round < 4; ++round) {
    if (2 * static_cast<Eigen::Index>(used.size()) <= n)
      throw_calibration_error("dlt_lmqn", "fewer residuals than free parameters");
    const ResidualFunction residual = [&](const Eigen::VectorXd& z, Eigen::VectorXd* r) {
      const Camera c = camera_at(base, spec, x0 + scale.cwiseProduct(z));
      r->resize(2 * static_cast<Eigen::Index>(used.size()));
      for (std::size_t k = 0; k < used.size(); ++k) {
        const auto& o = p.observations[used[k]];
        Eigen::Vector2d uv;
        if (!project(c, o.world, &uv)) return false;
        r->segment<2>(2 * static_cast<Eigen::Index>(k)) = W[used[k]] * (uv - o.pixel);
      }
      return true;
    };
    LmQnOptions lopt;
    lopt.eps_x = 1e-10;
    lopt.max_iterations = 300;
    lm = lm_qn_minimise(residual, JacobianFunction{}, Eigen::VectorXd::Zero(n), lopt);
    cam = camera_at(base, spec, x0 + scale.cwiseProduct(lm.x));
    std::vector<double> wn(p.observations.size(), std::numeric_limits<double>::infinity());
    std::vector<double> sorted;
    for (std::size_t i = 0; i < p.observations.size(); ++i) {
      Eigen::Vector2d uv;
      if (project(cam, p.observations[i].world, &uv)) wn[i] = (W[i] * (uv - p.observations[i].pixel)).norm();
    }
    for (std::size_t i : used) sorted.push_back(wn[i]);
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double robust = std::max(1.0, sorted[sorted.size() / 2] / std::sqrt(2 * std::log(2.0)));
    std::vector<std::size_t> next;
    for (std::size_t i = 0; i < wn.size(); ++i)
      if (wn[i] <= 4.0 * robust) next.push_back(i);
    if (next == used) break;
    used = next;
  }

  std::vector<std::size_t> rejected;
  for (std::size_t i = 0, k = 0; i < p.observations.size(); ++i) {
    if (k < used.size() && used[k] == i)
      ++k;
    else
      rejected.push_back(i);
  }
  CalibrationResult r = finish("dlt_lmqn", p, cam, rejected);
  // Covariance from the whitened Jacobian at the solution: (JᵀJ)⁻¹ in z, scaled back to x.
  const Eigen::MatrixXd JtJ = lm.jacobian.transpose() * lm.jacobian;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(JtJ);
  const double emax = es.eigenvalues().cwiseAbs().maxCoeff();
  if (es.eigenvalues().minCoeff() > 1e-12 * emax) {
    const Eigen::MatrixXd cov_z =
        es.eigenvectors() * es.eigenvalues().cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
    r.covariance = scale.asDiagonal() * cov_z * scale.asDiagonal();
    for (const auto& s : spec) r.parameter_names.push_back(s.name);
    const int ce = r.parameter_index("CE");
    if (ce >= 0) r.center_covariance_m2 = r.covariance.block<3, 3>(ce, ce);
  } else {
    r.warnings.push_back(
        "dlt_lmqn: the free parameters are not all determined by this geometry "
        "(normal matrix rank-deficient); no covariance");
  }
  r.details = {{"dlt_ransac_inliers", dlt.inliers.size()},
               {"final_inliers", used.size()},
               {"dlt_outliers", dlt.outliers.size()},
               {"dlt_ransac_iterations", dlt.ransac_iterations},
               {"dlt_rms_px", dlt.rms_px},
               {"dlt_skew_px", dlt.skew_px},
               {"lmqn_iterations", lm.iterations},
               {"lmqn_lm_steps", lm.lm_steps},
               {"lmqn_qn_steps", lm.qn_steps},
               {"lmqn_stop", lm.stop_reason},
               {"lmqn_chi2", 2 * lm.F}};
  return r;
}

}  // namespace

const std::vector<std::string>& calibration_method_names() {
  static const std::vector<std::string> names = {"tsai", "tsai_sassa", "dlt_lmqn", "bundle", "planar"};
  return names;
}

std::vector<Eigen::Vector2d> reprojection_residuals(const Camera& cam,
                                                    const std::vector<BundleObservation>& obs,
                                                    double clock_offset_s) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(obs.size());
  for (const auto& o : obs) {
    Eigen::Vector2d uv;
    out.push_back(project(cam, observed_world_point(o, clock_offset_s), &uv) ? Eigen::Vector2d(uv - o.pixel)
                                                                             : Eigen::Vector2d(kNaN, kNaN));
  }
  return out;
}

ReprojectionStats reprojection_stats(const std::vector<Eigen::Vector2d>& residuals,
                                     const std::vector<std::size_t>& rejected) {
  std::vector<bool> skip(residuals.size(), false);
  for (std::size_t i : rejected)
    if (i < skip.size()) skip[i] = true;
  ReprojectionStats s;
  double sum = 0, sum2 = 0, mx = 0;
  int n = 0;
  for (std::size_t i = 0; i < residuals.size(); ++i) {
    if (skip[i]) continue;
    const double d = residuals[i].norm();
    sum += d;
    sum2 += d * d;
    mx = std::max(mx, d);
    ++n;
  }
  s.n_used = n;
  s.n_rejected = static_cast<int>(rejected.size());
  if (n > 0) {
    s.rms_px = std::sqrt(sum2 / n);
    s.mean_px = sum / n;
    s.max_px = mx;
  }
  return s;
}

namespace {

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

}  // namespace

CalibrationResult calibrate_camera(const std::string& method, const CalibrationProblem& problem) {
  const auto t0 = std::chrono::steady_clock::now();
  CalibrationResult r;
  if (method != "planar") require_depth_beyond_noise(method, problem);
  if (method == "tsai")
    r = run_tsai(problem);
  else if (method == "tsai_sassa")
    r = run_tsai_sassa(problem);
  else if (method == "bundle")
    r = run_bundle(problem);
  else if (method == "dlt_lmqn")
    r = run_dlt_lmqn(problem);
  else if (method == "planar")
    throw Error(ErrorKind::usage, "", 0, "calibrate.method",
                "'planar' calibrates from several views of a planar target (seed 001); a lamp track is one "
                "view of non-coplanar points — use bundle, tsai, tsai_sassa or dlt_lmqn");
  else
    throw Error(ErrorKind::usage, "", 0, "calibrate.method", "unknown method '" + method + "'");
  if (method != "bundle" &&
      std::find(problem.free.begin(), problem.free.end(), "clock_offset") != problem.free.end())
    r.warnings.push_back("clock_offset is estimated by the bundle method only; " + method +
                         " takes the frame time stamps as exact (clock offset 0)");
  // Exact symmetry (round-off makes C and Cᵀ differ in the last bit; readers check symmetry).
  if (r.covariance.size() > 0) r.covariance = 0.5 * (r.covariance + r.covariance.transpose()).eval();
  r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace rangecal
