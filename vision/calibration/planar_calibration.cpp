#include "vision/calibration/planar_calibration.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

#include "config/error.hpp"
#include "vision/calibration/homography.hpp"
#include "vision/calibration/linear_distortion.hpp"
#include "vision/calibration/nearest_rotation.hpp"

namespace rangecal {
namespace {

const char* const kPlanarMethod = "planar";

// NOTES.md's V_ij of seed 001, without the B12 column (no skew): b = [B11, B22, B13, B23, B33].
Eigen::Matrix<double, 1, 5> v_row(const Eigen::Matrix3d& H, int i, int j) {
  const Eigen::Vector3d hi = H.col(i), hj = H.col(j);
  Eigen::Matrix<double, 1, 5> v;
  v << hi(0) * hj(0), hi(1) * hj(1), hi(2) * hj(0) + hi(0) * hj(2), hi(2) * hj(1) + hi(1) * hj(2),
      hi(2) * hj(2);
  return v;
}

struct PlanarResidual {
  double X, Y, u, v, dx, dy;
  template <typename T>
  bool operator()(const T* intr, const T* dist, const T* aa, const T* t, T* res) const {
    const T p[3] = {T(X), T(Y), T(0)};
    T xc[3];
    ceres::AngleAxisRotatePoint(aa, p, xc);
    for (int k = 0; k < 3; ++k) xc[k] += t[k];
    T uu, vv;
    if (!project_camera_point(intr, dist, dx, dy, xc, &uu, &vv)) return false;
    res[0] = uu - T(u);
    res[1] = vv - T(v);
    return true;
  }
};

double rms_of(const CameraIntrinsics& in, const std::vector<CameraPose>& poses,
              const std::vector<std::vector<PointCorrespondence>>& views) {
  double ss = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < views.size(); ++i) {
    Camera cam{"", in, poses[i]};
    for (const auto& p : views[i]) {
      Eigen::Vector2d uv;
      if (!project(cam, p.world, &uv)) return std::numeric_limits<double>::infinity();
      ss += (uv - p.pixel).squaredNorm();
      ++n;
    }
  }
  return std::sqrt(ss / n);
}

struct ClosedForm {
  Eigen::Matrix3d K;  ///< camera matrix, K(2, 2) = 1
  CameraIntrinsics in;
};

// Closed form in pixel coordinates normalised about the image centre (conditioning): N·K stays
// upper triangular without skew, so K = N⁻¹·K'.
ClosedForm closed_form_intrinsics(const std::vector<Eigen::Matrix3d>& homographies,
                                  const SensorGeometry& sensor) {
  const double s = 2.0 / std::max(1, sensor.width_px + sensor.height_px);
  Eigen::Matrix3d N;
  N << s, 0, -s * sensor.center_u_px(), 0, s, -s * sensor.center_v_px(), 0, 0, 1;
  Eigen::MatrixXd V(2 * homographies.size(), 5);
  for (std::size_t i = 0; i < homographies.size(); ++i) {
    Eigen::Matrix3d Hn = N * homographies[i];
    Hn /= Hn.norm();
    V.row(2 * i) = v_row(Hn, 0, 1);
    V.row(2 * i + 1) = v_row(Hn, 0, 0) - v_row(Hn, 1, 1);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(V, Eigen::ComputeFullV);
  const auto& sv = svd.singularValues();
  if (!sv.allFinite() || sv(3) < 1e-9 * sv(0))
    throw_calibration_error(kPlanarMethod,
                            "singular system in V·b = 0 (seed 001 eq. 8): the views do not constrain "
                            "the intrinsics (e.g. all target planes parallel)");
  Eigen::Matrix<double, 5, 1> b = svd.matrixV().col(4);
  if (b(0) < 0) b = -b;
  const double B11 = b(0), B22 = b(1), B13 = b(2), B23 = b(3), B33 = b(4);
  // NOTES.md's corrected eq. 9 (no skew).
  const double u0n = -B13 / B11, v0n = -B23 / B22;
  const double lam = B33 - B13 * B13 / B11 - B23 * B23 / B22;
  if (!(B11 > 0) || !(B22 > 0) || !(lam / B11 > 0) || !(lam / B22 > 0))
    throw_calibration_error(kPlanarMethod,
                            "B = C⁻ᵀC⁻¹ is not positive definite (noise or degenerate views): no real "
                            "focal length");
  Eigen::Matrix3d Kn;
  Kn << std::sqrt(lam / B11), 0, u0n, 0, std::sqrt(lam / B22), v0n, 0, 0, 1;
  ClosedForm cf;
  cf.K = N.inverse() * Kn;
  cf.K /= cf.K(2, 2);
  const Eigen::Matrix3d& K = cf.K;
  CameraIntrinsics& in = cf.in;
  in.width_px = sensor.width_px;
  in.height_px = sensor.height_px;
  in.dx_mm = sensor.dx_mm;
  in.dy_mm = sensor.dy_mm;
  in.f_mm = K(1, 1) * sensor.dy_mm;
  in.sx = K(0, 0) * sensor.dx_mm / in.f_mm;
  in.u0_px = K(0, 2);
  in.v0_px = K(1, 2);
  return cf;
}

// Extrinsics per view (seed 001 eq. 7 / Zhang §3.1).
std::vector<CameraPose> view_poses(const Eigen::Matrix3d& K,
                                   const std::vector<Eigen::Matrix3d>& homographies) {
  const Eigen::Matrix3d Ki = K.inverse();
  std::vector<CameraPose> poses;
  for (const Eigen::Matrix3d& H : homographies) {
    const Eigen::Vector3d a1 = Ki * H.col(0), a2 = Ki * H.col(1), a3 = Ki * H.col(2);
    double kappa = 2.0 / (a1.norm() + a2.norm());
    if (kappa * a3.z() < 0) kappa = -kappa;  // target in front of the camera
    Eigen::Matrix3d R;
    R.col(0) = kappa * a1;
    R.col(1) = kappa * a2;
    R.col(2) = R.col(0).cross(R.col(1));
    CameraPose pose;
    pose.R = nearest_rotation(R);
    pose.T = kappa * a3;
    poses.push_back(pose);
  }
  return poses;
}

// Nonlinear refinement of everything (pixel reprojection error), from res.intrinsics and res.poses.
void refine_planar(const std::vector<std::vector<PointCorrespondence>>& views, const SensorGeometry& sensor,
                   const PlanarOptions& opt, PlanarResult& res) {
  const CameraIntrinsics& in = res.intrinsics;
  double intr[4] = {in.f_mm, in.sx, in.u0_px, in.v0_px};
  auto dist = in.dist.as_array();
  std::vector<std::array<double, 6>> pose_params(views.size());
  ceres::Problem problem;
  for (std::size_t i = 0; i < views.size(); ++i) {
    const Eigen::AngleAxisd aa(res.poses[i].R);
    const Eigen::Vector3d w = aa.angle() * aa.axis();
    pose_params[i] = {w.x(), w.y(), w.z(), res.poses[i].T.x(), res.poses[i].T.y(), res.poses[i].T.z()};
    for (const auto& p : views[i]) {
      auto* cost = new ceres::AutoDiffCostFunction<PlanarResidual, 2, 4, 7, 3, 3>(
          new PlanarResidual{p.world.x(), p.world.y(), p.pixel.x(), p.pixel.y(), sensor.dx_mm, sensor.dy_mm});
      problem.AddResidualBlock(cost, nullptr, intr, dist.data(), pose_params[i].data(),
                               pose_params[i].data() + 3);
    }
  }
  std::vector<int> fixed_dist = {2, 3, 4, 5, 6};
  if (!opt.estimate_k2) fixed_dist.insert(fixed_dist.begin(), 1);
  problem.SetManifold(dist.data(), new ceres::SubsetManifold(7, fixed_dist));
  if (!opt.estimate_sx) {
    intr[1] = 1.0;
    problem.SetManifold(intr, new ceres::SubsetManifold(4, {1}));
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_SCHUR;
  so.max_num_iterations = opt.max_iterations;
  so.num_threads = 1;
  so.function_tolerance = 1e-15;
  so.gradient_tolerance = 1e-15;
  so.parameter_tolerance = 1e-15;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (!summary.IsSolutionUsable() || !(intr[0] > 0))
    throw_calibration_error(kPlanarMethod, "nonlinear refinement failed: " + summary.message);
  res.iterations = static_cast<int>(summary.iterations.size()) - 1;
  res.intrinsics.f_mm = intr[0];
  res.intrinsics.sx = intr[1];
  res.intrinsics.u0_px = intr[2];
  res.intrinsics.v0_px = intr[3];
  res.intrinsics.dist = Distortion::from_array(dist.data());
  for (std::size_t i = 0; i < views.size(); ++i) {
    const Eigen::Vector3d w(pose_params[i][0], pose_params[i][1], pose_params[i][2]);
    const double a = w.norm();
    res.poses[i].R = a > 0 ? Eigen::AngleAxisd(a, w / a).toRotationMatrix() : Eigen::Matrix3d::Identity();
    res.poses[i].T = {pose_params[i][3], pose_params[i][4], pose_params[i][5]};
  }
  res.rms_px = rms_of(res.intrinsics, res.poses, views);
}

}  // namespace

PlanarResult planar_calibrate(const std::vector<std::vector<PointCorrespondence>>& views,
                              const SensorGeometry& sensor, const PlanarOptions& opt) {
  if (!(sensor.dx_mm > 0) || !(sensor.dy_mm > 0) || !std::isfinite(sensor.dx_mm) ||
      !std::isfinite(sensor.dy_mm))
    throw_calibration_error(kPlanarMethod, "pixel pitch dx, dy must be finite and > 0 mm");
  if (views.size() < 2)
    throw_calibration_error(kPlanarMethod,
                            "too few views: " + std::to_string(views.size()) +
                                " given, at least 2 needed (4 unknowns of B up to scale, 2 equations "
                                "per view)");
  PlanarResult res;
  for (std::size_t i = 0; i < views.size(); ++i)
    res.homographies.push_back(fit_homography(views[i], "planar view " + std::to_string(i)));
  const ClosedForm cf = closed_form_intrinsics(res.homographies, sensor);
  CameraIntrinsics in = cf.in;
  res.poses = view_poses(cf.K, res.homographies);

  // Radial k1, k2 by linear least squares (seed 001 eqs. 14–16).
  std::vector<std::pair<CameraPose, std::vector<PointCorrespondence>>> vp;
  for (std::size_t i = 0; i < views.size(); ++i) vp.emplace_back(res.poses[i], views[i]);
  in.dist = fit_linear_distortion(in, vp, opt.estimate_k2 ? kRadialK1K2 : kRadialK1).dist;
  res.closed_form = in;
  res.closed_form_rms_px = rms_of(in, res.poses, views);
  res.intrinsics = in;
  res.rms_px = res.closed_form_rms_px;
  if (opt.refine) refine_planar(views, sensor, opt, res);
  return res;
}

}  // namespace rangecal
