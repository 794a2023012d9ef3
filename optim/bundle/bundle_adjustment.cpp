#include "optim/bundle/bundle_adjustment.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "config/error.hpp"

namespace rangecal {
namespace {

using Eigen::Matrix2d;
using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::VectorXd;

// Ambient parameter layout: four Ceres blocks.
constexpr int kIntr = 4;   // f, sx, u0, v0 (project_camera_point's intr order)
constexpr int kDist = 7;   // kDistortionNames order
constexpr int kPose = 6;   // wx wy wz (rad), CE CN CU (m)
constexpr int kClock = 1;  // clock_offset (s)
constexpr int kAll = kIntr + kDist + kPose + kClock;
constexpr int kClockIndex = kIntr + kDist + kPose;
constexpr std::array<const char*, kAll> kNames = {"f",  "sx", "u0", "v0", "k1", "k2",
                                                  "k3", "p1", "p2", "a1", "a2", "wx",
                                                  "wy", "wz", "CE", "CN", "CU", "clock_offset"};

/// A clock offset whose 1σ moves the fastest lamp point by more than this (m) is poorly determined:
/// twice the PPK noise of one epoch (docs/optimisation.md).
constexpr double kClockWarningM = 0.02;
/// Above this |δ| (s) the first-order model X − v·δ misses ½·a·δ² (≈ 2 mm at 1.5 m/s² and 50 ms):
/// the stamps should be corrected and the mission re-aligned instead.
constexpr double kLargeClockOffsetS = 0.05;

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

/// The parameters being estimated, as Ceres sees them. The rotation is a perturbation w about R0:
/// R = exp([w]×)·R0, re-based to w = 0 between stages so the covariance is about the final R.
struct ParameterState {
  double intr[kIntr];
  double dist[kDist];
  double pose[kPose];
  double clock[kClock] = {0};
  Matrix3d R0;

  static ParameterState from_camera(const Camera& c, double clock_offset_s = 0) {
    ParameterState s;
    s.clock[0] = clock_offset_s;
    s.intr[0] = c.intr.f_mm, s.intr[1] = c.intr.sx, s.intr[2] = c.intr.u0_px, s.intr[3] = c.intr.v0_px;
    const auto d = c.intr.dist.as_array();
    std::copy(d.begin(), d.end(), s.dist);
    const Vector3d C = c.pose.center();
    s.pose[0] = s.pose[1] = s.pose[2] = 0;
    s.pose[3] = C.x(), s.pose[4] = C.y(), s.pose[5] = C.z();
    s.R0 = c.pose.R;
    return s;
  }
  Camera to_camera(const Camera& base) const {
    Camera c = base;
    c.intr.f_mm = intr[0], c.intr.sx = intr[1], c.intr.u0_px = intr[2], c.intr.v0_px = intr[3];
    c.intr.dist = Distortion::from_array(dist);
    Matrix3d dR;
    ceres::AngleAxisToRotationMatrix(pose, ceres::ColumnMajorAdapter3x3(dR.data()));
    c.pose.R = dR * R0;
    const Vector3d C(pose[3], pose[4], pose[5]);
    c.pose.T = -c.pose.R * C;
    return c;
  }
};

/// Whitened reprojection residual of one point:
///   X  = Xw − v·δ                                (the lamp at the true exposure time, δ the clock
///                                                 offset; bundle_adjustment.hpp)
///   Xc = exp([w]×)·R0·(X − C)                    (SPEC §2, T = −R·C)
///   (u, v) = project_camera_point(intr, dist, Xc)  (seed 002 eqs. 6–7 + seed 000 eq. 7)
///   r = W·((u, v) − (u_obs, v_obs)),  W = L⁻¹, C_eff = L·Lᵀ
struct ReprojectionResidual {
  Vector3d Xw;
  Vector3d vel;
  Vector2d uv;
  Matrix2d W;
  Matrix3d R0;
  double dx_mm, dy_mm;

  template <typename T>
  bool operator()(const T* intr, const T* dist, const T* pose, const T* clock, T* residual) const {
    const T d[3] = {T(Xw.x()) - T(vel.x()) * clock[0] - pose[3], T(Xw.y()) - T(vel.y()) * clock[0] - pose[4],
                    T(Xw.z()) - T(vel.z()) * clock[0] - pose[5]};
    T q[3];
    for (int i = 0; i < 3; ++i) q[i] = T(R0(i, 0)) * d[0] + T(R0(i, 1)) * d[1] + T(R0(i, 2)) * d[2];
    T xc[3];
    ceres::AngleAxisRotatePoint(pose, q, xc);
    T u, v;
    if (!project_camera_point(intr, dist, dx_mm, dy_mm, xc, &u, &v)) return false;
    const T eu = u - T(uv.x()), ev = v - T(uv.y());
    residual[0] = T(W(0, 0)) * eu + T(W(0, 1)) * ev;
    residual[1] = T(W(1, 0)) * eu + T(W(1, 1)) * ev;
    return true;
  }
};

/// Principal-point prior: ((u0 − ū0)/σ, (v0 − v̄0)/σ).
struct PrincipalPointPrior {
  Vector2d p;
  double sigma;
  template <typename T>
  bool operator()(const T* intr, T* residual) const {
    residual[0] = (intr[2] - T(p.x())) / T(sigma);
    residual[1] = (intr[3] - T(p.y())) / T(sigma);
    return true;
  }
};

/// Camera-centre prior: (C − C̄)/σ per ENU axis.
struct CenterPrior {
  Vector3d c;
  Vector3d sigma;
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    for (int i = 0; i < 3; ++i) residual[i] = (pose[3 + i] - T(c[i])) / T(sigma[i]);
    return true;
  }
};

using ReprojectionCost = ceres::AutoDiffCostFunction<ReprojectionResidual, 2, kIntr, kDist, kPose, kClock>;
using PrincipalPointCost = ceres::AutoDiffCostFunction<PrincipalPointPrior, 2, kIntr>;
using CenterCost = ceres::AutoDiffCostFunction<CenterPrior, 3, kPose>;

/// Effective image covariance C = σ²I + J_X Σ_X J_Xᵀ and its whitening W = L⁻¹.
Matrix2d whitening(const Camera& cam, const BundleObservation& o, double sigma_px) {
  const Eigen::Matrix<double, 2, 3> JX = pixel_jacobian_wrt_world(cam, o.world);
  const Matrix2d C = sigma_px * sigma_px * Matrix2d::Identity() + JX * o.world_cov * JX.transpose();
  const Matrix2d L = C.llt().matrixL();
  return L.inverse();
}

struct Setup {
  std::array<bool, kAll> free{};
  int n_free = 0;
  bool pp_prior = false;
  bool center_prior = false;
};

ceres::Manifold* subset_manifold(const bool* free, int size) {
  std::vector<int> constant;
  for (int i = 0; i < size; ++i)
    if (!free[i]) constant.push_back(i);
  if (constant.empty() || static_cast<int>(constant.size()) == size) return nullptr;
  return new ceres::SubsetManifold(size, constant);
}

/// One Levenberg–Marquardt solve over the used points with fixed weights. Returns iterations.
int solve_stage(ParameterState& st, const Camera& base, const std::vector<BundleObservation>& obs,
                const std::vector<char>& used, const std::vector<Matrix2d>& W, const Setup& setup,
                const BundleOptions& opt, RobustLoss loss) {
  ceres::Problem problem;
  ceres::LossFunction* lf = nullptr;
  if (loss == RobustLoss::huber) lf = new ceres::HuberLoss(opt.loss_scale);
  if (loss == RobustLoss::cauchy) lf = new ceres::CauchyLoss(opt.loss_scale);
  bool lf_used = false;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    if (!used[i]) continue;
    auto* cost = new ReprojectionCost(new ReprojectionResidual{
        obs[i].world, obs[i].velocity, obs[i].pixel, W[i], st.R0, base.intr.dx_mm, base.intr.dy_mm});
    problem.AddResidualBlock(cost, lf, st.intr, st.dist, st.pose, st.clock);
    lf_used = lf_used || lf;
  }
  if (lf && !lf_used) delete lf;
  if (setup.pp_prior)
    problem.AddResidualBlock(new PrincipalPointCost(new PrincipalPointPrior{
                                 opt.priors.principal_point_px, opt.priors.principal_point_sigma_px}),
                             nullptr, st.intr);
  if (setup.center_prior)
    problem.AddResidualBlock(
        new CenterCost(new CenterPrior{opt.priors.center_enu_m, opt.priors.center_sigma_m}), nullptr,
        st.pose);
  double* blocks[4] = {st.intr, st.dist, st.pose, st.clock};
  const int sizes[4] = {kIntr, kDist, kPose, kClock};
  int offset = 0;
  for (int b = 0; b < 4; ++b) {
    const bool* fr = setup.free.data() + offset;
    const int nf = static_cast<int>(std::count(fr, fr + sizes[b], true));
    if (nf == 0)
      problem.SetParameterBlockConstant(blocks[b]);
    else if (ceres::Manifold* m = subset_manifold(fr, sizes[b]))
      problem.SetManifold(blocks[b], m);
    offset += sizes[b];
  }
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = opt.max_iterations;
  so.function_tolerance = 1e-14;
  so.gradient_tolerance = 1e-16;
  so.parameter_tolerance = 1e-14;
  so.num_threads = 1;  // deterministic and cheap: ≤ 17 parameters
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (!summary.IsSolutionUsable() || !std::isfinite(summary.final_cost))
    throw_calibration_error("bundle", "Levenberg–Marquardt failed: " + summary.message);
  // Re-base the rotation: R0 ← exp([w]×)·R0, w ← 0.
  const Camera c = st.to_camera(base);
  const ParameterState re = ParameterState::from_camera(c);
  std::copy(re.pose, re.pose + kPose, st.pose);
  st.R0 = re.R0;
  return static_cast<int>(summary.iterations.size());
}

/// Whitened Jacobian rows (ambient, kAll columns) and residuals of the used points and priors.
void assemble(const ParameterState& st, const Camera& base, const std::vector<BundleObservation>& obs,
              const std::vector<char>& used, const std::vector<Matrix2d>& W, const Setup& setup,
              const BundleOptions& opt, MatrixXd* J, VectorXd* r) {
  int rows = 0;
  for (char u : used) rows += u ? 2 : 0;
  rows += (setup.pp_prior ? 2 : 0) + (setup.center_prior ? 3 : 0);
  J->setZero(rows, kAll);
  r->setZero(rows);
  const double* params[4] = {st.intr, st.dist, st.pose, st.clock};
  int row = 0;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    if (!used[i]) continue;
    ReprojectionCost cost(new ReprojectionResidual{obs[i].world, obs[i].velocity, obs[i].pixel, W[i], st.R0,
                                                   base.intr.dx_mm, base.intr.dy_mm});
    Eigen::Matrix<double, 2, kIntr, Eigen::RowMajor> j0;
    Eigen::Matrix<double, 2, kDist, Eigen::RowMajor> j1;
    Eigen::Matrix<double, 2, kPose, Eigen::RowMajor> j2;
    Eigen::Matrix<double, 2, kClock> j3;  // one column: row-major is not allowed (and the same)
    double* jac[4] = {j0.data(), j1.data(), j2.data(), j3.data()};
    double res[2];
    if (!cost.Evaluate(params, res, jac))
      throw_calibration_error("bundle",
                              "observation " + std::to_string(i) + " cannot be projected at the solution");
    J->block(row, 0, 2, kIntr) = j0;
    J->block(row, kIntr, 2, kDist) = j1;
    J->block(row, kIntr + kDist, 2, kPose) = j2;
    J->block(row, kClockIndex, 2, kClock) = j3;
    (*r)[row] = res[0], (*r)[row + 1] = res[1];
    row += 2;
  }
  if (setup.pp_prior) {
    const double s = opt.priors.principal_point_sigma_px;
    (*J)(row, 2) = 1 / s, (*J)(row + 1, 3) = 1 / s;
    (*r)[row] = (st.intr[2] - opt.priors.principal_point_px.x()) / s;
    (*r)[row + 1] = (st.intr[3] - opt.priors.principal_point_px.y()) / s;
    row += 2;
  }
  if (setup.center_prior) {
    for (int a = 0; a < 3; ++a) {
      const double s = opt.priors.center_sigma_m[a];
      (*J)(row + a, kIntr + kDist + 3 + a) = 1 / s;
      (*r)[row + a] = (st.pose[3 + a] - opt.priors.center_enu_m[a]) / s;
    }
  }
}

Setup make_setup(const std::vector<std::string>& free, const BundleOptions& opt) {
  Setup s;
  for (const auto& name : free) {
    bool known = false;
    for (int i = 0; i < kAll; ++i)
      if (name == kNames[i]) s.free[i] = known = true;
    if (name == "pose" || name == "rotation")
      for (int i = 0; i < 3; ++i) s.free[kIntr + kDist + i] = known = true;
    if (name == "pose" || name == "center")
      for (int i = 3; i < 6; ++i) s.free[kIntr + kDist + i] = known = true;
    if (!known)
      throw_config_error(
          "", "calibrate.free",
          "unknown parameter '" + name +
              "' (expected f, sx, u0, v0, k1, k2, k3, p1, p2, a1, a2, pose, rotation, center, clock_offset)");
  }
  s.n_free = static_cast<int>(std::count(s.free.begin(), s.free.end(), true));
  const int o = kIntr + kDist;
  s.pp_prior = opt.priors.use_principal_point && (s.free[2] || s.free[3]);
  s.center_prior = opt.priors.use_center && (s.free[o + 3] || s.free[o + 4] || s.free[o + 5]);
  return s;
}

void check_input(const Camera& cam, const std::vector<BundleObservation>& obs, const Setup& setup,
                 const BundleOptions& opt) {
  const auto& in = cam.intr;
  if (!(in.f_mm > 0 && in.dx_mm > 0 && in.dy_mm > 0 && in.sx > 0 && std::isfinite(in.u0_px) &&
        std::isfinite(in.v0_px)))
    throw_calibration_error(
        "bundle.initial",
        "the initial camera needs f > 0, pixel pitch > 0, sx > 0 and a finite principal point");
  if (!cam.pose.R.allFinite() || !cam.pose.T.allFinite() ||
      (cam.pose.R * cam.pose.R.transpose() - Matrix3d::Identity()).norm() > 1e-6)
    throw_calibration_error("bundle.initial", "the initial rotation is not a finite rotation matrix");
  if (setup.n_free == 0) throw_calibration_error("bundle", "no free parameters");
  if (!(opt.pixel_sigma_px > 0)) throw_calibration_error("bundle.pixel_sigma_px", "must be > 0");
  if (setup.pp_prior &&
      !(opt.priors.principal_point_sigma_px > 0 && opt.priors.principal_point_px.allFinite()))
    throw_calibration_error("priors.principal_point_sigma_px",
                            "the principal-point prior needs a finite value and σ > 0");
  if (setup.center_prior &&
      !((opt.priors.center_sigma_m.array() > 0).all() && opt.priors.center_enu_m.allFinite()))
    throw_calibration_error("priors.center_sigma_m",
                            "the camera-centre prior needs a finite value and σ > 0");
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const auto& o = obs[i];
    const std::string at = "observation " + std::to_string(i + 1);
    if (!o.world.allFinite())
      throw_calibration_error(at + ".world", "E, N, U must be finite (got NaN or infinity)");
    if (!o.pixel.allFinite())
      throw_calibration_error(at + ".pixel", "u, v must be finite (got NaN or infinity)");
    if (!o.world_cov.allFinite() || o.world_cov.diagonal().minCoeff() < 0)
      throw_calibration_error(at + ".world_cov",
                              "the world-point covariance must be finite and non-negative");
    if (!std::isfinite(o.pixel_sigma_px)) throw_calibration_error(at + ".pixel_sigma_px", "must be finite");
    if (!o.velocity.allFinite())
      throw_calibration_error(at + ".velocity", "the lamp velocity must be finite (got NaN or infinity)");
  }
  if (setup.free[kClockIndex] && std::none_of(obs.begin(), obs.end(), [](const BundleObservation& ob) {
        return ob.velocity.norm() > 0;
      }))
    throw_calibration_error("bundle.clock_offset",
                            "the clock offset is free but no observation carries a lamp velocity "
                            "(correspondences.csv without vE,vN,vU, or a lamp that never moved): rerun the "
                            "align and detect stages, or fix clock_offset");
  const int n = static_cast<int>(obs.size());
  if (2 * n < setup.n_free)
    throw_calibration_error("bundle", "fewer observations than unknowns: " + std::to_string(n) +
                                          " points give " + std::to_string(2 * n) + " equations for " +
                                          std::to_string(setup.n_free) + " free parameters");
  const int o = kIntr + kDist;
  const bool pose_free = std::any_of(setup.free.begin() + o, setup.free.end(), [](bool b) { return b; });
  if (pose_free && n >= 2) {
    Vector3d mean = Vector3d::Zero();
    for (const auto& ob : obs) mean += ob.world;
    mean /= n;
    MatrixXd P(n, 3);
    for (int i = 0; i < n; ++i) P.row(i) = (obs[i].world - mean).transpose();
    const Vector3d s = Eigen::JacobiSVD<MatrixXd>(P).singularValues();
    if (!(s[0] > 0)) throw_calibration_error("bundle", "all " + std::to_string(n) + " world points coincide");
    if (s[1] <= 1e-6 * s[0])
      throw_calibration_error(
          "bundle", "all " + std::to_string(n) +
                        " world points lie on one line (e.g. a single vertical ascent): the "
                        "camera's rotation about that line is undetermined; add points off the line");
  }
  int behind = 0;
  for (const auto& ob : obs)
    if (!(world_to_camera(cam.pose, ob.world).z() > 0)) ++behind;
  if (behind > 0)
    throw_calibration_error("bundle.initial",
                            std::to_string(behind) + " of " + std::to_string(n) +
                                " points are behind the initial camera (Zc ≤ 0): wrong starting pose");
}

}  // namespace

Eigen::Matrix<double, 2, 3> pixel_jacobian_wrt_world(const Camera& cam, const Vector3d& Xw) {
  using J3 = ceres::Jet<double, 3>;
  J3 X[3] = {J3(Xw.x(), 0), J3(Xw.y(), 1), J3(Xw.z(), 2)};
  J3 xc[3];
  for (int i = 0; i < 3; ++i)
    xc[i] = J3(cam.pose.T[i]) + cam.pose.R(i, 0) * X[0] + cam.pose.R(i, 1) * X[1] + cam.pose.R(i, 2) * X[2];
  const J3 intr[4] = {J3(cam.intr.f_mm), J3(cam.intr.sx), J3(cam.intr.u0_px), J3(cam.intr.v0_px)};
  const auto d = cam.intr.dist.as_array();
  J3 dist[7];
  for (int i = 0; i < 7; ++i) dist[i] = J3(d[i]);
  J3 u, v;
  project_camera_point(intr, dist, cam.intr.dx_mm, cam.intr.dy_mm, xc, &u, &v);
  Eigen::Matrix<double, 2, 3> J;
  J.row(0) = u.v.transpose();
  J.row(1) = v.v.transpose();
  return J;
}

BundleResult bundle_adjust(const Camera& initial, const std::vector<BundleObservation>& obs,
                           const BundleOptions& opt) {
  const Setup setup = make_setup(opt.free, opt);
  check_input(initial, obs, setup, opt);
  const std::size_t n = obs.size();
  double max_speed = 0;  // m/s, scales the clock offset in the rank test and its warning
  for (const auto& o : obs) max_speed = std::max(max_speed, o.velocity.norm());

  // SPEC §4.4: a fixed principal point stays at its prior when one is given.
  Camera start = initial;
  if (opt.priors.use_principal_point && opt.priors.principal_point_px.allFinite()) {
    if (!setup.free[2]) start.intr.u0_px = opt.priors.principal_point_px.x();
    if (!setup.free[3]) start.intr.v0_px = opt.priors.principal_point_px.y();
  }
  auto sigma_of = [&](const BundleObservation& o) {
    return o.pixel_sigma_px > 0 ? o.pixel_sigma_px : opt.pixel_sigma_px;
  };
  auto weights = [&](const Camera& c) {
    std::vector<Matrix2d> W(n);
    for (std::size_t i = 0; i < n; ++i) W[i] = whitening(c, obs[i], sigma_of(obs[i]));
    return W;
  };

  BundleResult out;
  ParameterState st = ParameterState::from_camera(start, opt.initial_clock_offset_s);
  std::vector<char> used(n, 1);
  nlohmann::json stages = nlohmann::json::array();

  // Stage A: robust solve with weights at the starting camera.
  std::vector<Matrix2d> W = weights(start);
  int it = solve_stage(st, start, obs, used, W, setup, opt, opt.loss);
  out.iterations += it;
  stages.push_back({{"loss", opt.loss == RobustLoss::none    ? "none"
                             : opt.loss == RobustLoss::huber ? "huber"
                                                             : "cauchy"},
                    {"iterations", it}});

  // Outliers at the stage-A solution (weights refreshed there).
  auto flag = [&](const Camera& c, const std::vector<Matrix2d>& Wc) {
    out.residual_px.assign(n, Vector2d::Zero());
    out.whitened_norm.assign(n, 0);
    std::vector<double> norms;
    for (std::size_t i = 0; i < n; ++i) {
      Vector2d uv;
      if (!project(c, observed_world_point(obs[i], st.clock[0]), &uv))
        uv.setConstant(std::numeric_limits<double>::infinity());
      out.residual_px[i] = uv - obs[i].pixel;
      out.whitened_norm[i] = (Wc[i] * out.residual_px[i]).norm();
      if (used[i]) norms.push_back(out.whitened_norm[i]);
    }
    std::nth_element(norms.begin(), norms.begin() + norms.size() / 2, norms.end());
    const double s = norms.empty() ? 1.0 : norms[norms.size() / 2] / std::sqrt(2 * std::log(2.0));
    const double thr = opt.outlier_threshold * std::max(1.0, s);
    out.outlier.assign(n, false);
    for (std::size_t i = 0; i < n; ++i) out.outlier[i] = !(out.whitened_norm[i] <= thr);
    return thr;
  };
  Camera cam = st.to_camera(start);
  W = weights(cam);
  double threshold = flag(cam, W);

  // Stage B: plain least squares on the inliers, weights refreshed (iterated effective variance).
  if (opt.resolve_without_outliers) {
    for (std::size_t i = 0; i < n; ++i)
      if (out.outlier[i]) used[i] = 0, out.calibration.rejected.push_back(i);
    const int n_used = static_cast<int>(std::count(used.begin(), used.end(), 1));
    if (2 * n_used < setup.n_free)
      throw_calibration_error("bundle", "after rejecting " + std::to_string(n - n_used) +
                                            " outliers too few points remain (" + std::to_string(n_used) +
                                            ")");
    it = solve_stage(st, start, obs, used, W, setup, opt, RobustLoss::none);
    out.iterations += it;
    stages.push_back({{"loss", "none"}, {"iterations", it}, {"rejected", n - n_used}});
    cam = st.to_camera(start);
    W = weights(cam);
    std::vector<bool> dropped = out.outlier;
    threshold = flag(cam, W);
    out.outlier = dropped;  // the listed outliers are the ones dropped
  }

  // Covariance from the whitened Jacobian at the solution (w re-based to 0).
  MatrixXd Jall;
  VectorXd r;
  assemble(st, start, obs, used, W, setup, opt, &Jall, &r);
  std::vector<int> cols;
  std::vector<std::string> names;
  for (int i = 0; i < kAll; ++i)
    if (setup.free[i]) cols.push_back(i), names.push_back(kNames[i]);
  const int p = static_cast<int>(cols.size());
  MatrixXd J(Jall.rows(), p);
  for (int k = 0; k < p; ++k) J.col(k) = Jall.col(cols[k]);
  out.chi2 = r.squaredNorm();
  out.dof = static_cast<int>(J.rows()) - p;
  out.variance_factor = out.dof > 0 ? out.chi2 / out.dof : std::numeric_limits<double>::quiet_NaN();

  auto& cal = out.calibration;
  cal.camera_id = initial.id;
  cal.method = "bundle";
  cal.camera = cam;
  cal.clock_offset_s = st.clock[0];
  cal.parameter_names = names;

  const MatrixXd N = J.transpose() * J;
  VectorXd scale(p);
  std::vector<std::string> undetermined;
  for (int k = 0; k < p; ++k) {
    scale[k] = N(k, k) > 0 ? 1 / std::sqrt(N(k, k)) : 0;
    if (!(N(k, k) > 0)) undetermined.push_back(names[k]);
  }
  if (!undetermined.empty()) {
    out.rank_deficient = true;
    std::string list;
    for (const auto& u : undetermined) list += (list.empty() ? "" : ", ") + u;
    cal.warnings.push_back("covariance is rank-deficient: the data do not depend on " + list +
                           " at all (fix it or add observations that do)");
  } else {
    // Rank test on columns scaled by each parameter's physical range (a full-size change of every
    // parameter: f, the image, 1/r_max^k for the distortion terms, 1 rad, the camera distance), so
    // a parameter whose column is only rounding noise is not rescued by Jacobi scaling.
    const auto& in = cam.intr;
    const double rmax = 0.5 * std::hypot(in.width_px * in.dx_mm, in.height_px * in.dy_mm);
    Vector3d mean = Vector3d::Zero();
    for (const auto& ob : obs) mean += ob.world / static_cast<double>(n);
    const double dist = std::max(1.0, (cam.pose.center() - mean).norm());
    const double typical[kAll] = {in.f_mm,
                                  1.0,
                                  static_cast<double>(std::max(in.width_px, 1)),
                                  static_cast<double>(std::max(in.height_px, 1)),
                                  std::pow(rmax, -2),
                                  std::pow(rmax, -4),
                                  std::pow(rmax, -6),
                                  1 / rmax,
                                  1 / rmax,
                                  1,
                                  1,
                                  1,
                                  1,
                                  1,
                                  dist,
                                  dist,
                                  dist,
                                  dist / std::max(max_speed, 1e-3)};
    VectorXd tscale(p);
    for (int k = 0; k < p; ++k) tscale[k] = typical[cols[k]];
    Eigen::SelfAdjointEigenSolver<MatrixXd> et(tscale.asDiagonal() * N * tscale.asDiagonal());
    const VectorXd lt = et.eigenvalues();
    const MatrixXd Ns = scale.asDiagonal() * N * scale.asDiagonal();
    Eigen::SelfAdjointEigenSolver<MatrixXd> es(Ns);
    const VectorXd lam = es.eigenvalues();
    if (!(lt[0] > opt.rank_tolerance * lt[p - 1]) || !(lam[0] > opt.rank_tolerance * lam[p - 1])) {
      out.rank_deficient = true;
      const bool phys = !(lt[0] > opt.rank_tolerance * lt[p - 1]);
      const VectorXd nullv = phys ? VectorXd(et.eigenvectors().col(0)) : VectorXd(es.eigenvectors().col(0));
      std::string list;
      for (int k = 0; k < p; ++k)
        if (std::abs(nullv[k]) > 0.2) list += (list.empty() ? "" : ", ") + names[k];
      cal.warnings.push_back("covariance is rank-deficient: " + list +
                             " cannot be determined from these data; fix some of them or add a prior");
    } else {
      const MatrixXd Nsi =
          es.eigenvectors() * lam.cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
      out.covariance_unscaled = scale.asDiagonal() * Nsi * scale.asDiagonal();
      out.covariance_scaled =
          out.covariance_unscaled * (std::isfinite(out.variance_factor) ? out.variance_factor : 1.0);
      cal.covariance = opt.scale_covariance ? out.covariance_scaled : out.covariance_unscaled;
    }
  }

  // Camera-centre covariance: its own block when the centre is free; zero when held fixed.
  const int o = kIntr + kDist;
  cal.center_covariance_m2.setZero();
  if (cal.covariance.rows() == p) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const int ia = cal.parameter_index(kNames[o + 3 + a]), ib = cal.parameter_index(kNames[o + 3 + b]);
        if (ia >= 0 && ib >= 0) cal.center_covariance_m2(a, b) = cal.covariance(ia, ib);
      }
  } else {
    cal.center_covariance_m2.setConstant(std::numeric_limits<double>::quiet_NaN());
  }

  // Reprojection statistics over the points used.
  double s2 = 0, s1 = 0, mx = 0;
  int nu = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!used[i]) continue;
    const double e = out.residual_px[i].norm();
    s2 += e * e, s1 += e, mx = std::max(mx, e), ++nu;
  }
  cal.reprojection.n_used = nu;
  cal.reprojection.n_rejected = static_cast<int>(n) - nu;
  if (nu > 0)
    cal.reprojection.rms_px = std::sqrt(s2 / nu), cal.reprojection.mean_px = s1 / nu,
    cal.reprojection.max_px = mx;

  // Warnings for poorly determined parameters (docs/optimisation.md).
  if (cal.covariance.rows() == p) {
    const auto& in = cam.intr;
    const double hw = std::max(in.u0_px, in.width_px - 1 - in.u0_px) * in.dx_mm / in.sx;
    const double hh = std::max(in.v0_px, in.height_px - 1 - in.v0_px) * in.dy_mm;
    const double rmax = std::sqrt(hw * hw + hh * hh);  // sensor mm to the farthest corner
    const double pix = std::min(in.dx_mm, in.dy_mm);
    for (int k = 0; k < p; ++k) {
      const double s = std::sqrt(cal.covariance(k, k));
      const std::string& nm = names[k];
      double effect_px = -1, limit = 0;
      std::string why;
      if (nm == "f" && s > 0.01 * in.f_mm) why = "σ " + fmt(s) + " mm is more than 1 % of f";
      if ((nm == "u0" && s > 0.05 * in.width_px) || (nm == "v0" && s > 0.05 * in.height_px))
        why = "σ " + fmt(s) + " px is more than 5 % of the image size";
      if (nm == "sx" && s > 0.01) why = "σ " + fmt(s) + " is more than 0.01";
      if (nm == "k1") effect_px = s * std::pow(rmax, 3) / pix, limit = 1;
      if (nm == "k2") effect_px = s * std::pow(rmax, 5) / pix, limit = 1;
      if (nm == "k3") effect_px = s * std::pow(rmax, 7) / pix, limit = 1;
      if (nm == "p1" || nm == "p2") effect_px = s * 3 * rmax * rmax / pix, limit = 1;
      if (nm == "a1" || nm == "a2") effect_px = s * rmax / pix, limit = 1;
      if (effect_px > limit)
        why = "a 1σ change moves the image corner by " + fmt(effect_px) + " px (> " + fmt(limit) + " px)";
      if ((nm == "wx" || nm == "wy" || nm == "wz") && s > 1e-3)
        why = "σ " + fmt(s) + " rad is more than 1 mrad";
      if ((nm == "CE" || nm == "CN" || nm == "CU") && s > 1.0) why = "σ " + fmt(s) + " m is more than 1 m";
      if (nm == "clock_offset" && s * max_speed > kClockWarningM)
        why = "σ " + fmt(s * 1e3) + " ms moves the fastest lamp point (" + fmt(max_speed) + " m/s) by " +
              fmt(s * max_speed * 100) + " cm (> 2 cm); fly faster ascents and descents, or fix it";
      if (!why.empty()) cal.warnings.push_back("parameter " + nm + " is poorly determined: " + why);
    }
    for (int a = 0; a < p; ++a)
      for (int b = a + 1; b < p; ++b) {
        const double rho = cal.correlation(names[a], names[b]);
        if (std::abs(rho) > opt.correlation_warning)
          cal.warnings.push_back("parameters " + names[a] + " and " + names[b] + " are correlated (ρ = " +
                                 fmt(rho) + "): the data cannot separate them; fix one or add a prior");
      }
  }
  if (setup.free[kClockIndex] && std::abs(cal.clock_offset_s) > kLargeClockOffsetS)
    cal.warnings.push_back("clock offset " + fmt(cal.clock_offset_s * 1e3) +
                           " ms is large for the first-order model X − v·δ (it misses ½·a·δ², " +
                           fmt(0.5 * 1.5 * cal.clock_offset_s * cal.clock_offset_s * 1e3) +
                           " mm at 1.5 m/s²): shift the frame time stamps by it and rerun align, detect and "
                           "calibrate");
  if (out.dof > 0) {
    // χ² test at the 1 % level (Wilson–Hilferty approximation of the χ² quantile).
    const double k = out.dof, z = 2.326;
    const double q99 = k * std::pow(1 - 2 / (9 * k) + z * std::sqrt(2 / (9 * k)), 3);
    if (out.chi2 > q99)
      cal.warnings.push_back("a-posteriori variance factor " + fmt(out.variance_factor) +
                             " exceeds 1: the assumed pixel/PPK noise is too optimistic or the model misses "
                             "something; σ scaled by √factor are in details.sigma_scaled");
  } else {
    cal.warnings.push_back("no redundancy (dof = 0): the variance factor and outlier test are meaningless");
  }

  // Deterministic details for calibration.json.
  nlohmann::json d;
  d["free"] = names;
  d["stages"] = stages;
  d["iterations"] = out.iterations;
  d["chi2"] = out.chi2;
  d["dof"] = out.dof;
  d["variance_factor"] = out.variance_factor;
  d["covariance_scaled_by_variance_factor"] = opt.scale_covariance;
  d["rank_deficient"] = out.rank_deficient;
  d["outlier_threshold_sigma"] = threshold;
  d["pixel_sigma_px"] = opt.pixel_sigma_px;
  if (setup.free[kClockIndex]) d["clock_offset_s"] = cal.clock_offset_s;
  if (out.covariance_unscaled.rows() == p) {
    nlohmann::json su, ss;
    for (int k = 0; k < p; ++k) {
      su[names[k]] = std::sqrt(out.covariance_unscaled(k, k));
      ss[names[k]] = std::sqrt(out.covariance_scaled(k, k));
    }
    d["sigma_unscaled"] = su;
    d["sigma_scaled"] = ss;
  }
  std::vector<std::size_t> outl;
  for (std::size_t i = 0; i < n; ++i)
    if (out.outlier[i]) outl.push_back(i);
  d["outliers"] = outl;
  cal.details = d;
  return out;
}

}  // namespace rangecal
