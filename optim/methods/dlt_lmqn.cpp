#include "optim/methods/dlt_lmqn.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "config/error.hpp"
#include "optim/bundle/whitening.hpp"
#include "optim/estimation/robust_scale.hpp"
#include "vision/calibration/linear_distortion.hpp"

namespace rangecal {
namespace {

std::vector<PointCorrespondence> to_points(const std::vector<BundleObservation>& obs) {
  std::vector<PointCorrespondence> pts;
  pts.reserve(obs.size());
  for (const auto& o : obs) pts.push_back({o.world, o.pixel});
  return pts;
}

/// The DLT camera on the sensor, with the parameters that are not free held at their fixed values
/// and the free distortion terms at their linear values (seed 000 eq. 8) from the RANSAC inliers.
Camera starting_camera(const DltResult& dlt, const std::vector<PointCorrespondence>& pts,
                       const SensorGeometry& sensor, const DltLmqnOptions& o) {
  Camera base = dlt.camera;
  base.intr.width_px = sensor.width_px;
  base.intr.height_px = sensor.height_px;
  base.intr.dx_mm = sensor.dx_mm;
  base.intr.dy_mm = sensor.dy_mm;
  hold_fixed_intrinsics(o.free, o.fixed_principal_point_px, &base.intr);
  DistortionTerms terms{};
  bool any_distortion = false;
  for (std::size_t k = 0; k < 7; ++k)
    any_distortion |= (terms[k] = contains(o.free, kDistortionParameters[k]));
  std::vector<PointCorrespondence> inliers;
  for (std::size_t i : dlt.inliers) inliers.push_back(pts[i]);
  if (any_distortion) base.intr.dist = fit_linear_distortion(base, inliers, terms).dist;
  return base;
}

/// Indices whose whitened residual at `cam` is within the robust threshold outlier_sigma·max(1, s)
/// of the `used` points (optim/estimation/robust_scale.hpp).
std::vector<std::size_t> inliers_at(const Camera& cam, const std::vector<BundleObservation>& obs,
                                    const std::vector<Eigen::Matrix2d>& W,
                                    const std::vector<std::size_t>& used, double outlier_sigma) {
  std::vector<double> wn(obs.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < obs.size(); ++i) {
    Eigen::Vector2d uv;
    if (project(cam, obs[i].world, &uv)) wn[i] = (W[i] * (uv - obs[i].pixel)).norm();
  }
  std::vector<double> used_norms;
  for (std::size_t i : used) used_norms.push_back(wn[i]);
  const double threshold = robust_outlier_threshold(outlier_sigma, std::move(used_norms));
  std::vector<std::size_t> next;
  for (std::size_t i = 0; i < wn.size(); ++i)
    if (wn[i] <= threshold) next.push_back(i);
  return next;
}

}  // namespace

DltLmqnResult dlt_lmqn_calibrate(const std::vector<BundleObservation>& obs, const SensorGeometry& sensor,
                                 const DltLmqnOptions& o) {
  DltLmqnResult res;
  const std::vector<PointCorrespondence> pts = to_points(obs);
  DltOptions dopt;
  dopt.seed = o.seed;
  dopt.inlier_threshold_px = o.ransac_threshold_px;
  res.dlt = dlt_calibrate(pts, sensor, dopt);
  res.start = starting_camera(res.dlt, pts, sensor, o);
  const Camera& base = res.start;
  const std::vector<Eigen::Matrix2d> W = whitening_matrices(base, obs, o.pixel_sigma_px);

  for (CameraParameter p : o.free)
    if (p != CameraParameter::clock_offset) res.parameters.push_back(p);
  const auto n = static_cast<Eigen::Index>(res.parameters.size());
  const Eigen::VectorXd x0 = parameter_values(base, res.parameters);
  Eigen::VectorXd scale(n);
  for (Eigen::Index i = 0; i < n; ++i) scale[i] = parameter_info(res.parameters[std::size_t(i)]).search_scale;

  res.used = res.dlt.inliers;
  res.camera = base;
  for (int round = 0; round < 4; ++round) {
    if (2 * static_cast<Eigen::Index>(res.used.size()) <= n)
      throw_calibration_error("dlt_lmqn", "fewer residuals than free parameters");
    const std::vector<std::size_t>& used = res.used;
    const ResidualFunction residual = [&](const Eigen::VectorXd& z, Eigen::VectorXd* r) {
      const Camera c = camera_with_parameters(base, res.parameters, x0 + scale.cwiseProduct(z));
      r->resize(2 * static_cast<Eigen::Index>(used.size()));
      for (std::size_t k = 0; k < used.size(); ++k) {
        const auto& ob = obs[used[k]];
        Eigen::Vector2d uv;
        if (!project(c, ob.world, &uv)) return false;
        r->segment<2>(2 * static_cast<Eigen::Index>(k)) = W[used[k]] * (uv - ob.pixel);
      }
      return true;
    };
    LmQnOptions lopt;
    lopt.eps_x = 1e-10;
    lopt.max_iterations = 300;
    res.lmqn = lm_qn_minimise(residual, JacobianFunction{}, Eigen::VectorXd::Zero(n), lopt);
    res.camera = camera_with_parameters(base, res.parameters, x0 + scale.cwiseProduct(res.lmqn.x));
    std::vector<std::size_t> next = inliers_at(res.camera, obs, W, res.used, o.outlier_sigma);
    if (next == res.used) break;
    res.used = std::move(next);
  }
  for (std::size_t i = 0, k = 0; i < obs.size(); ++i) {
    if (k < res.used.size() && res.used[k] == i)
      ++k;
    else
      res.rejected.push_back(i);
  }

  // Covariance from the whitened Jacobian at the solution: (JᵀJ)⁻¹ in z, scaled back to x.
  const Eigen::MatrixXd JtJ = res.lmqn.jacobian.transpose() * res.lmqn.jacobian;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(JtJ);
  const double emax = es.eigenvalues().cwiseAbs().maxCoeff();
  if (es.eigenvalues().minCoeff() > 1e-12 * emax) {
    const Eigen::MatrixXd cov_z =
        es.eigenvectors() * es.eigenvalues().cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
    res.covariance = scale.asDiagonal() * cov_z * scale.asDiagonal();
  }
  return res;
}

}  // namespace rangecal
