#include "vision/triangulation/triangulation.hpp"

#include <ceres/jet.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
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

// 2. Gauss–Newton on the reprojection error weighted by W (2n×2n, the views' pixels stacked), from
// `start`; sets point and adds to iterations.
void gauss_newton_point(const std::vector<TriangulationView>& views, const ViewParameters& vp,
                        const Eigen::MatrixXd& W, const Eigen::Vector3d& start, const std::string& what,
                        TriangulationResult& res) {
  const std::size_t n = views.size();
  Eigen::Vector3d X = start;
  Eigen::MatrixXd J(2 * n, 3);
  Eigen::VectorXd r(2 * n);
  bool converged = false;
  for (int it = 0; it < 50 && !converged; ++it) {
    for (std::size_t i = 0; i < n; ++i) {
      const ProjectionDerivatives pd = differentiate(views[i].camera, vp.center_mode[i] != 0, X, false);
      if (!(pd.depth > 0)) behind_camera(what, views[i].camera, pd.depth);
      const auto row = static_cast<Eigen::Index>(2 * i);
      J.block<2, 3>(row, 0) = pd.d_point;
      r.segment<2>(row) = pd.uv - views[i].uv_px;
    }
    const Eigen::MatrixXd WJ = W * J;
    const Eigen::Matrix3d N = J.transpose() * WJ;
    const Eigen::Vector3d step = -N.ldlt().solve(WJ.transpose() * r);
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

// The calibrations' covariance between views i and j carried through M (per view, its columns the
// view's calibration parameters: K_i to the pixels, ∂X/∂θ_i to the point), M_i·Σ_ij·M_jᵀ — Σ_ii a
// camera's own covariance, Σ_ij a cross block when `cross` gives one; none (empty) without.
Eigen::MatrixXd projected_calibration(const std::vector<TriangulationView>& views,
                                      const std::vector<Eigen::MatrixXd>& M, const CrossCovariances* cross,
                                      std::size_t i, std::size_t j, const std::string& what) {
  if (M[i].size() == 0 || M[j].size() == 0) return {};
  if (i == j) return M[i] * views[i].calibration.covariance * M[i].transpose();
  if (!cross || i >= cross->size() || j >= (*cross)[i].size() || (*cross)[i][j].size() == 0) return {};
  const Eigen::MatrixXd& S = (*cross)[i][j];
  if (S.rows() != M[i].cols() || S.cols() != M[j].cols())
    throw_calibration_error(what, "a cross-camera covariance block does not match the cameras' parameters");
  return M[i] * S * M[j].transpose();
}

// The views' pixel errors' covariance, stacked (2n×2n): each view's label and timing terms
// (view_covariance) and, with `K` (the calibrations' pixel Jacobians; all empty: none), the
// calibrations' K_i·Σ_ij·K_jᵀ, cross blocks included — what one draw of every error moves the
// residuals by. Its inverse is the weight of the generalised least-squares point.
Eigen::MatrixXd stacked_covariance(const std::vector<TriangulationView>& views,
                                   const std::vector<Eigen::MatrixXd>& K, const CrossCovariances* cross,
                                   const std::string& what) {
  const std::size_t n = views.size();
  Eigen::MatrixXd C =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(2 * n), static_cast<Eigen::Index>(2 * n));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      const auto ri = static_cast<Eigen::Index>(2 * i), cj = static_cast<Eigen::Index>(2 * j);
      if (i == j) C.block<2, 2>(ri, cj) = view_covariance(views[i]);
      const Eigen::MatrixXd P = projected_calibration(views, K, cross, i, j, what);
      if (P.size() > 0) C.block<2, 2>(ri, cj) += P;
    }
  return 0.5 * (C + C.transpose());
}

// C⁻¹, after checking C is positive definite: with every covariance positive semi-definite it is
// (the labels' σ > 0); a calibration's or a network's covariance that is not makes it fail, named.
Eigen::MatrixXd weight_of(const Eigen::MatrixXd& C, const std::vector<TriangulationView>& views,
                          const std::string& what) {
  const Eigen::LLT<Eigen::MatrixXd> llt(C);
  if (llt.info() == Eigen::Success) return llt.solve(Eigen::MatrixXd::Identity(C.rows(), C.cols()));
  std::string ids;
  for (std::size_t i = 0; i < views.size(); ++i) {
    const auto ri = static_cast<Eigen::Index>(2 * i);
    if (Eigen::LLT<Eigen::Matrix2d>(Eigen::Matrix2d(C.block<2, 2>(ri, ri))).info() != Eigen::Success)
      throw_calibration_error(
          "camera " + views[i].camera.id + " covariance",
          "is not positive semi-definite: its pixel covariance at " + what + " is not positive definite");
    ids += (ids.empty() ? "" : ", ") + views[i].camera.id;
  }
  throw_calibration_error(what, "the joint calibration covariance of cameras " + ids +
                                    " (its cross blocks) is not positive semi-definite");
}

// 3. Covariance at res.point of the estimate weighted by W (2n×2n): with J the views' ∂pixel/∂X
// stacked, N = JᵀWJ and A = N⁻¹JᵀW, each part A·(its term of the stacked covariance)·Aᵀ — the
// labels', the timing's, and the calibrations' through ∂X/∂θ_i = −A_i·K_i (K_i = `K[i]`, with the
// cross-camera blocks). When W is the inverse of the whole stacked covariance the parts sum to N⁻¹.
// With `residuals`, each view's residual, their rms and rᵀWr as well.
void covariance_at(const std::vector<TriangulationView>& views, const ViewParameters& vp,
                   const Eigen::MatrixXd& W, const std::vector<Eigen::MatrixXd>& K, const std::string& what,
                   const CrossCovariances* cross, bool residuals, TriangulationResult& res) {
  const std::size_t n = views.size();
  const Eigen::Vector3d& X = res.point;
  Eigen::MatrixXd J(2 * n, 3);
  Eigen::VectorXd r(2 * n);
  double sum_sq = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const ProjectionDerivatives pd = differentiate(views[i].camera, vp.center_mode[i] != 0, X, false);
    if (!(pd.depth > 0)) behind_camera(what, views[i].camera, pd.depth);
    const auto row = static_cast<Eigen::Index>(2 * i);
    J.block<2, 3>(row, 0) = pd.d_point;
    r.segment<2>(row) = pd.uv - views[i].uv_px;
    if (!residuals) continue;
    res.residuals_px.push_back(r.segment<2>(row));
    sum_sq += r.segment<2>(row).squaredNorm();
  }
  if (residuals) {
    res.rms_px = std::sqrt(sum_sq / static_cast<double>(n));
    res.weighted_chi2 = r.dot(W * r);
  }
  const Eigen::MatrixXd JtW = J.transpose() * W;
  const Eigen::Matrix3d Ninv = (JtW * J).inverse();
  if (!Ninv.allFinite())
    throw_calibration_error(what, "the views' normal equations are singular: the rays are (nearly) parallel");
  const Eigen::MatrixXd A = Ninv * JtW;  // 3×2n: ∂X/∂(pixels)
  Eigen::Matrix3d pick = Eigen::Matrix3d::Zero(), timing = Eigen::Matrix3d::Zero();
  std::vector<Eigen::MatrixXd> dXs(n);
  for (std::size_t i = 0; i < n; ++i) {
    const TriangulationView& v = views[i];
    const Eigen::Matrix<double, 3, 2> Ai = A.block<3, 2>(0, static_cast<Eigen::Index>(2 * i));
    pick += v.pick_sigma_px * v.pick_sigma_px * Ai * Ai.transpose();
    const Eigen::Vector3d Ag = Ai * v.image_velocity_px_s;
    timing += v.timing_sigma_s * v.timing_sigma_s * Ag * Ag.transpose();
    if (K[i].size() == 0) continue;
    dXs[i] = -Ai * K[i];  // ∂X/∂θ_i, 3×m
  }
  res.cov_pick_m2 = 0.5 * (pick + pick.transpose());
  res.cov_timing_m2 = 0.5 * (timing + timing.transpose());
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      const Eigen::MatrixXd part = projected_calibration(views, dXs, cross, i, j, what);
      if (part.size() > 0) res.cov_calibration_m2 += part;
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
  // The views' own terms alone: block-diagonal, each 2×2 block inverted (view_covariance ≥ σ²·I).
  Eigen::MatrixXd W =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(2 * n), static_cast<Eigen::Index>(2 * n));
  for (std::size_t i = 0; i < n; ++i) {
    const auto r = static_cast<Eigen::Index>(2 * i);
    W.block<2, 2>(r, r) = view_covariance(views[i]).inverse();
  }
  gauss_newton_point(views, vp, W, res.linear_point, what, res);
  // The calibrations' errors are part of the views' errors, shared between cameras calibrated
  // together: weighed with them (the stacked covariance at this first solution, its Jacobians
  // serving the covariance below too: the second solve moves the point by a fraction of its σ),
  // the point is the generalised least-squares one, the most precise linear estimate when the
  // covariances hold (Gauss–Markov theorem), and its covariance is N⁻¹.
  const std::vector<Eigen::MatrixXd> K = calibration_jacobians(views, vp, res.point, what);
  bool calibrated = false;
  for (const Eigen::MatrixXd& k : K) calibrated = calibrated || k.size() > 0;
  if (calibrated) {
    W = weight_of(stacked_covariance(views, K, cross, what), views, what);
    gauss_newton_point(views, vp, W, res.point, what, res);
  }
  covariance_at(views, vp, W, K, what, cross, true, res);
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
  // The rays through X's pixels must meet (no prediction where they are nearly parallel) in front
  // of every camera, as triangulate_point asks.
  std::vector<TriangulationView> at_x = views;
  for (TriangulationView& v : at_x)
    if (!project(v.camera, X, &v.uv_px)) behind_camera(what, v.camera, world_to_camera(v.camera.pose, X).z());
  linear_midpoint(at_x, what, res);
  res.point = X;
  res.linear_point = X;
  const std::vector<Eigen::MatrixXd> K = calibration_jacobians(views, vp, X, what);
  const Eigen::MatrixXd W =
      weight_of(stacked_covariance(views, weigh_calibration ? K : std::vector<Eigen::MatrixXd>(views.size()),
                                   weigh_calibration ? cross : nullptr, what),
                views, what);
  covariance_at(views, vp, W, K, what, cross, false, res);
  return res;
}

}  // namespace rangecal
