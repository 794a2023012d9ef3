#include "vision/triangulation/triangulation.hpp"

#include <ceres/jet.h>
#include <ceres/rotation.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <cstdio>

#include "config/error.hpp"
#include "config/number_format.hpp"

namespace rangecal {

namespace {

constexpr int kNumParams = kCameraParameterCount;
constexpr int kF = index_of(CameraParameter::f), kSx = index_of(CameraParameter::sx),
              kU0 = index_of(CameraParameter::u0), kV0 = index_of(CameraParameter::v0),
              kK1 = index_of(CameraParameter::k1), kW = index_of(CameraParameter::wx),
              kT = index_of(CameraParameter::Tx), kC = index_of(CameraParameter::CE);

/// Indices of `parameters` in the canonical order; sets *center_mode unless they use T. Throws
/// for T mixed with C.
std::vector<int> parameter_indices(const std::vector<CameraParameter>& parameters, const std::string& cam_id,
                                   bool* center_mode) {
  std::vector<int> idx;
  bool has_t = false, has_c = false;
  for (CameraParameter p : parameters) {
    has_t = has_t || is_translation(p);
    has_c = has_c || is_center(p);
    idx.push_back(index_of(p));
  }
  if (has_t && has_c) {
    throw_calibration_error(
        "camera " + cam_id + " covariance",
        "mixes translation (Tx Ty Tz) and centre (CE CN CU) parameters; use one pose form");
  }
  *center_mode = !has_t;
  return idx;
}

/// Pixel of world point X through `cam` perturbed by q (kNumParams values, canonical order).
/// Centre mode: Xc = exp([w]×)·R̂·(X − Ĉ − δC); translation mode: Xc = exp([w]×)·R̂·X + T̂ + δT.
template <typename T>
bool project_perturbed(const Camera& cam, bool center_mode, const T* X, const T* q, T* uv, T* depth) {
  const Eigen::Matrix3d& R = cam.pose.R;
  const Eigen::Vector3d C = cam.pose.center();
  T y[3], xc[3];
  if (center_mode) {
    const T rel[3] = {X[0] - C.x() - q[kC], X[1] - C.y() - q[kC + 1], X[2] - C.z() - q[kC + 2]};
    for (int r = 0; r < 3; ++r) y[r] = R(r, 0) * rel[0] + R(r, 1) * rel[1] + R(r, 2) * rel[2];
    ceres::AngleAxisRotatePoint(q + kW, y, xc);
  } else {
    for (int r = 0; r < 3; ++r) y[r] = R(r, 0) * X[0] + R(r, 1) * X[1] + R(r, 2) * X[2];
    ceres::AngleAxisRotatePoint(q + kW, y, xc);
    for (int r = 0; r < 3; ++r) xc[r] += cam.pose.T[r] + q[kT + r];
  }
  *depth = xc[2];
  const CameraIntrinsics& in = cam.intr;
  const T intr[4] = {in.f_mm + q[kF], in.sx + q[kSx], in.u0_px + q[kU0], in.v0_px + q[kV0]};
  const auto d0 = in.dist.as_array();
  T d[7];
  for (int k = 0; k < 7; ++k) d[k] = d0[k] + q[kK1 + k];
  return project_camera_point(intr, d, in.dx_mm, in.dy_mm, xc, &uv[0], &uv[1]);
}

/// Pixel, ∂pixel/∂X and (optionally) ∂pixel/∂θ for all kNumParams parameters.
struct ProjectionDerivatives {
  Eigen::Vector2d uv;
  Eigen::Matrix<double, 2, 3> d_point;
  Eigen::Matrix<double, 2, kNumParams> d_params;
  double depth = 0;
  bool ok = false;
};

ProjectionDerivatives differentiate(const Camera& cam, bool center_mode, const Eigen::Vector3d& X,
                                    bool with_params) {
  ProjectionDerivatives out;
  if (with_params) {
    using J = ceres::Jet<double, 3 + kNumParams>;
    J x[3], q[kNumParams], uv[2], depth;
    for (int k = 0; k < 3; ++k) x[k] = J(X[k], k);
    for (int k = 0; k < kNumParams; ++k) q[k] = J(0.0, 3 + k);
    out.ok = project_perturbed(cam, center_mode, x, q, uv, &depth);
    out.depth = depth.a;
    for (int r = 0; r < 2; ++r) {
      out.uv[r] = uv[r].a;
      out.d_point.row(r) = uv[r].v.template head<3>().transpose();
      out.d_params.row(r) = uv[r].v.template tail<kNumParams>().transpose();
    }
  } else {
    using J = ceres::Jet<double, 3>;
    J x[3], q[kNumParams], uv[2], depth;
    for (int k = 0; k < 3; ++k) x[k] = J(X[k], k);
    for (int k = 0; k < kNumParams; ++k) q[k] = J(0.0);
    out.ok = project_perturbed(cam, center_mode, x, q, uv, &depth);
    out.depth = depth.a;
    for (int r = 0; r < 2; ++r) {
      out.uv[r] = uv[r].a;
      out.d_point.row(r) = uv[r].v.transpose();
    }
    out.d_params.setZero();
  }
  return out;
}

[[noreturn]] void behind_camera(const std::string& what, const Camera& cam, double depth) {
  throw_calibration_error(what, "the triangulated point lies behind camera " + cam.id + " (depth " +
                                    format_number("%.3f", depth) +
                                    " m): the rays do not meet in front of every camera — check the picks "
                                    "and the calibrations");
}

// Each view's parameter indices and pose form, after checking its pixel, pick σ and covariance.
struct ViewParameters {
  std::vector<std::vector<int>> param_idx;
  std::vector<char> center_mode;
};

ViewParameters validated_views(const std::vector<TriangulationView>& views, const std::string& what) {
  const std::size_t n = views.size();
  ViewParameters vp;
  vp.param_idx.resize(n);
  vp.center_mode.assign(n, 1);
  for (std::size_t i = 0; i < n; ++i) {
    const TriangulationView& v = views[i];
    if (!(std::isfinite(v.uv_px.x()) && std::isfinite(v.uv_px.y())))
      throw_input_error("", 0, "u,v", what + ": the pixel seen by camera " + v.camera.id + " is not finite");
    if (!(std::isfinite(v.pick_sigma_px) && v.pick_sigma_px > 0))
      throw_input_error("", 0, "pick_sigma_px",
                        what + ": camera " + v.camera.id + " pick σ must be positive, got " +
                            format_number("%g", v.pick_sigma_px));
    if (!(std::isfinite(v.timing_sigma_s) && v.timing_sigma_s >= 0 && v.image_velocity_px_s.allFinite()))
      throw_input_error("", 0, "timing_sigma_s",
                        what + ": camera " + v.camera.id +
                            " timing σ must be finite and not negative, its image velocity finite");
    bool cm = true;
    vp.param_idx[i] = parameter_indices(v.calibration.parameters, v.camera.id, &cm);
    vp.center_mode[i] = cm;
    const auto m = static_cast<Eigen::Index>(vp.param_idx[i].size());
    const Eigen::MatrixXd& S = v.calibration.covariance;
    if (S.rows() != m || S.cols() != m)
      throw_calibration_error("camera " + v.camera.id + " covariance",
                              "is " + std::to_string(S.rows()) + "×" + std::to_string(S.cols()) + " for " +
                                  std::to_string(m) + " parameters");
    if (m > 0 && !S.allFinite())
      throw_calibration_error("camera " + v.camera.id + " covariance", "has non-finite entries");
  }
  return vp;
}

// A view's pixel covariance: the pick's σ²·I and, for a moving point, the image motion over the
// view's time error, σ_t²·g·gᵀ (g the pixel velocity): a label whose instant is off by δt lies δt·g
// along the image track.
Eigen::Matrix2d view_covariance(const TriangulationView& v) {
  return v.pick_sigma_px * v.pick_sigma_px * Eigen::Matrix2d::Identity() +
         v.timing_sigma_s * v.timing_sigma_s * v.image_velocity_px_s * v.image_velocity_px_s.transpose();
}

// 1. Linear: least-squares midpoint of the rays; sets linear_point and max_ray_angle_deg.
void linear_midpoint(const std::vector<TriangulationView>& views, const std::string& what,
                     TriangulationResult& res) {
  const std::size_t n = views.size();
  std::vector<Eigen::Vector3d> dirs(n);
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    dirs[i] = pixel_ray_world(views[i].camera, views[i].uv_px);
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - dirs[i] * dirs[i].transpose();
    A += P;
    b += P * views[i].camera.pose.center();
  }
  double max_angle = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      max_angle = std::max(max_angle, std::atan2(dirs[i].cross(dirs[j]).norm(), dirs[i].dot(dirs[j])));
  res.max_ray_angle_deg = max_angle * 57.295779513082320876;  // 180/π
  if (!(max_angle >= 1e-4)) {
    throw_calibration_error(what, "the viewing rays are parallel (largest angle between them " +
                                      format_number("%.2e", max_angle) +
                                      " rad): no intersection; the cameras see the "
                                      "point from the same direction");
  }
  res.linear_point = A.ldlt().solve(b);
  for (std::size_t i = 0; i < n; ++i) {
    const double depth = world_to_camera(views[i].camera.pose, res.linear_point).z();
    if (!(depth > 0)) behind_camera(what, views[i].camera, depth);
  }
}

// 2. Gauss–Newton on the reprojection error weighted by W_i = `weights[i]`, from `start`; sets point
// and adds to iterations.
void gauss_newton_point(const std::vector<TriangulationView>& views, const ViewParameters& vp,
                        const std::vector<Eigen::Matrix2d>& weights, const Eigen::Vector3d& start,
                        const std::string& what, TriangulationResult& res) {
  const std::size_t n = views.size();
  Eigen::Vector3d X = start;
  Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
  bool converged = false;
  for (int it = 0; it < 50 && !converged; ++it) {
    N.setZero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < n; ++i) {
      const ProjectionDerivatives pd = differentiate(views[i].camera, vp.center_mode[i] != 0, X, false);
      if (!(pd.depth > 0)) behind_camera(what, views[i].camera, pd.depth);
      N += pd.d_point.transpose() * weights[i] * pd.d_point;
      g += pd.d_point.transpose() * weights[i] * (pd.uv - views[i].uv_px);
    }
    const Eigen::Vector3d step = -N.ldlt().solve(g);
    if (!step.allFinite()) throw_calibration_error(what, "the reprojection normal equations are singular");
    X += step;
    ++res.iterations;
    converged = step.norm() < 1e-10 * (1.0 + X.norm());
  }
  if (!converged)
    throw_calibration_error(what, "the nonlinear triangulation did not converge in 50 iterations");
  res.point = X;
}

// Each view's ∂pixel/∂θ over its calibration's parameters at X (2×m; empty without a covariance).
std::vector<Eigen::MatrixXd> calibration_jacobians(const std::vector<TriangulationView>& views,
                                                   const ViewParameters& vp, const Eigen::Vector3d& X,
                                                   const std::string& what) {
  std::vector<Eigen::MatrixXd> J(views.size());
  for (std::size_t i = 0; i < views.size(); ++i) {
    const std::vector<int>& idx = vp.param_idx[i];
    if (idx.empty()) continue;
    const ProjectionDerivatives pd = differentiate(views[i].camera, vp.center_mode[i] != 0, X, true);
    if (!(pd.depth > 0)) behind_camera(what, views[i].camera, pd.depth);
    J[i].resize(2, static_cast<Eigen::Index>(idx.size()));
    for (std::size_t k = 0; k < idx.size(); ++k)
      J[i].col(static_cast<Eigen::Index>(k)) = pd.d_params.col(idx[k]);
  }
  return J;
}

// The weights W_i = (σ_px²·I + σ_t²·g·gᵀ + J_θi·Σ_θi·J_θiᵀ)⁻¹ (the last term only `with_calibration`):
// with it, the generalised least-squares weights of a point whose views' errors are the labels',
// their instants' and their cameras' calibrations' (the cross-camera blocks left out of the weights;
// the covariance below carries them).
std::vector<Eigen::Matrix2d> view_weights(const std::vector<TriangulationView>& views,
                                          const std::vector<Eigen::MatrixXd>& jacobians,
                                          bool with_calibration) {
  std::vector<Eigen::Matrix2d> W(views.size());
  for (std::size_t i = 0; i < views.size(); ++i) {
    Eigen::Matrix2d C = view_covariance(views[i]);
    if (with_calibration && jacobians[i].size() > 0)
      C += jacobians[i] * views[i].calibration.covariance * jacobians[i].transpose();
    W[i] = C.inverse();
  }
  return W;
}

// 3. Covariance at res.point of the estimate weighted by W_i = `weights[i]`: with N = Σ J_iᵀW_iJ_i
// and A_i = N⁻¹J_iᵀW_i, the labels' part Σ A_i·σ²I·A_iᵀ, the timing's Σ A_i·σ_t²ggᵀ·A_iᵀ, the
// calibration's through ∂X/∂θ_i = −A_i·J_θi (J_θi = `jacobians[i]`, and the cross-camera blocks);
// with `residuals`, each view's residual and their rms as well.
void covariance_at(const std::vector<TriangulationView>& views, const ViewParameters& vp,
                   const std::vector<Eigen::Matrix2d>& weights, const std::vector<Eigen::MatrixXd>& jacobians,
                   const std::string& what, const CrossCovariances* cross, bool residuals,
                   TriangulationResult& res) {
  const std::size_t n = views.size();
  const Eigen::Vector3d& X = res.point;
  Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
  std::vector<ProjectionDerivatives> pds(n);
  const std::vector<Eigen::Matrix2d>& Ws = weights;
  double sum_sq = 0;
  for (std::size_t i = 0; i < n; ++i) {
    pds[i] = differentiate(views[i].camera, vp.center_mode[i] != 0, X, false);
    if (!(pds[i].depth > 0)) behind_camera(what, views[i].camera, pds[i].depth);
    N += pds[i].d_point.transpose() * Ws[i] * pds[i].d_point;
    if (!residuals) continue;
    res.residuals_px.push_back(pds[i].uv - views[i].uv_px);
    sum_sq += res.residuals_px.back().squaredNorm();
  }
  if (residuals) res.rms_px = std::sqrt(sum_sq / static_cast<double>(n));
  const Eigen::Matrix3d Ninv = N.inverse();
  Eigen::Matrix3d pick = Eigen::Matrix3d::Zero(), timing = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Matrix<double, 3, 2> JW = pds[i].d_point.transpose() * Ws[i];
    const TriangulationView& v = views[i];
    pick += v.pick_sigma_px * v.pick_sigma_px * JW * JW.transpose();
    const Eigen::Vector3d Jg = JW * v.image_velocity_px_s;
    timing += v.timing_sigma_s * v.timing_sigma_s * Jg * Jg.transpose();
  }
  res.cov_pick_m2 = Ninv * pick * Ninv;
  res.cov_pick_m2 = 0.5 * (res.cov_pick_m2 + res.cov_pick_m2.transpose()).eval();
  res.cov_timing_m2 = Ninv * timing * Ninv;
  res.cov_timing_m2 = 0.5 * (res.cov_timing_m2 + res.cov_timing_m2.transpose()).eval();
  std::vector<Eigen::MatrixXd> dXs(n);
  res.calibration_pixel_cov.assign(n, Eigen::Matrix2d::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::MatrixXd& Jt = jacobians[i];
    if (Jt.size() == 0) continue;
    const Eigen::MatrixXd dX = -Ninv * (pds[i].d_point.transpose() * Ws[i]) * Jt;  // ∂X/∂θ_i, 3×m
    res.cov_calibration_m2 += dX * views[i].calibration.covariance * dX.transpose();
    res.calibration_pixel_cov[i] = Jt * views[i].calibration.covariance * Jt.transpose();
    dXs[i] = dX;
  }
  if (cross)
    for (std::size_t i = 0; i < n && i < cross->size(); ++i)
      for (std::size_t j = 0; j < n && j < (*cross)[i].size(); ++j) {
        const Eigen::MatrixXd& C = (*cross)[i][j];
        if (i == j || C.size() == 0 || dXs[i].size() == 0 || dXs[j].size() == 0) continue;
        if (C.rows() != dXs[i].cols() || C.cols() != dXs[j].cols())
          throw_calibration_error(what,
                                  "a cross-camera covariance block does not match the cameras' parameters");
        res.cov_calibration_m2 += dXs[i] * C * dXs[j].transpose();
      }
  res.cov_calibration_m2 = 0.5 * (res.cov_calibration_m2 + res.cov_calibration_m2.transpose()).eval();
  res.cov_m2 = res.cov_pick_m2 + res.cov_timing_m2 + res.cov_calibration_m2;
  res.sigma_m = std::sqrt(res.cov_m2.trace());
}

}  // namespace

Eigen::MatrixXd pixel_jacobian_wrt_parameters(const Camera& camera,
                                              const std::vector<CameraParameter>& parameters,
                                              const Eigen::Vector3d& X,
                                              Eigen::Matrix<double, 2, 3>* d_point) {
  bool center_mode = true;
  const std::vector<int> idx = parameter_indices(parameters, camera.id, &center_mode);
  const ProjectionDerivatives pd = differentiate(camera, center_mode, X, true);
  if (!(pd.depth > 0)) behind_camera("camera " + camera.id + " Jacobian", camera, pd.depth);
  Eigen::MatrixXd J(2, static_cast<Eigen::Index>(idx.size()));
  for (std::size_t k = 0; k < idx.size(); ++k) J.col(static_cast<Eigen::Index>(k)) = pd.d_params.col(idx[k]);
  if (d_point) *d_point = pd.d_point;
  return J;
}

TriangulationResult triangulate_point(const std::vector<TriangulationView>& views, const std::string& what,
                                      const CrossCovariances* cross) {
  const std::size_t n = views.size();
  if (n < 2) {
    throw_calibration_error(
        what, "seen by " + std::to_string(n) + " calibrated camera(s); triangulation needs at least two");
  }
  const ViewParameters vp = validated_views(views, what);
  TriangulationResult res;
  linear_midpoint(views, what, res);
  std::vector<Eigen::Matrix2d> weights = view_weights(views, std::vector<Eigen::MatrixXd>(n), false);
  gauss_newton_point(views, vp, weights, res.linear_point, what, res);
  // The calibrations' errors are part of each view's error: weighed with them (at the first
  // solution; one more solve), the point is the generalised least-squares one, never less precise
  // than the labels' weights give when the covariances hold (Gauss–Markov theorem).
  // The calibration's Jacobians at that first solution serve the weights and the covariance alike
  // (the second solve moves the point by a fraction of its σ: a change of second order).
  const std::vector<Eigen::MatrixXd> jacobians = calibration_jacobians(views, vp, res.point, what);
  bool calibrated = false;
  for (const Eigen::MatrixXd& J : jacobians) calibrated = calibrated || J.size() > 0;
  if (calibrated) {
    weights = view_weights(views, jacobians, true);
    gauss_newton_point(views, vp, weights, res.point, what, res);
  }
  covariance_at(views, vp, weights, jacobians, what, cross, true, res);
  return res;
}

TriangulationResult triangulation_covariance_at(const std::vector<TriangulationView>& views,
                                                const Eigen::Vector3d& X, const CrossCovariances* cross,
                                                bool weigh_calibration) {
  const std::string what = "the point " + format_number("(%.3f", X.x()) + format_number(", %.3f", X.y()) +
                           format_number(", %.3f)", X.z());
  if (views.size() < 2)
    throw_calibration_error(what, "seen by " + std::to_string(views.size()) +
                                      " calibrated camera(s); an intersection needs at least two");
  const ViewParameters vp = validated_views(views, what);
  TriangulationResult res;
  res.point = X;
  res.linear_point = X;
  const std::vector<Eigen::MatrixXd> jacobians = calibration_jacobians(views, vp, X, what);
  covariance_at(views, vp, view_weights(views, jacobians, weigh_calibration), jacobians, what, cross, false,
                res);
  return res;
}

}  // namespace rangecal
