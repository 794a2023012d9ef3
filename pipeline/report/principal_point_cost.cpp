#include "pipeline/report/principal_point_cost.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>

#include "vision/triangulation/triangulation.hpp"

namespace rangecal {
namespace {

const std::vector<CameraParameter> kPrincipalPoint = {CameraParameter::u0, CameraParameter::v0};

/// The calibration's parameters without the clock offset, which a static point's pixel does not
/// depend on (its column would leave F singular).
std::vector<CameraParameter> propagated(const CalibrationResult& r) {
  std::vector<CameraParameter> p;
  for (CameraParameter q : r.parameters)
    if (q != CameraParameter::clock_offset) p.push_back(q);
  return p;
}

bool holds_principal_point_fixed(const CalibrationResult& r) {
  return r.parameter_index(CameraParameter::u0) < 0 && r.parameter_index(CameraParameter::v0) < 0;
}

/// G = F⁻¹ Σ_i J_iᵀ W_i P_i (parameters × 2): δθ = G·δ for a principal-point shift δ (file comment).
/// Empty when F is singular or no pair is usable.
Eigen::MatrixXd absorption(const CalibrationResult& r, const std::vector<Correspondence>& pairs,
                           double pixel_sigma_px, double default_sd_m) {
  const std::vector<CameraParameter> params = propagated(r);
  const auto n = static_cast<Eigen::Index>(params.size());
  Eigen::MatrixXd F = Eigen::MatrixXd::Zero(n, n), B = Eigen::MatrixXd::Zero(n, 2);
  int used = 0;
  for (const Correspondence& c : pairs) {
    if (c.used && !*c.used) continue;
    if (!(world_to_camera(r.camera.pose, c.enu).z() > 0)) continue;
    Eigen::Matrix<double, 2, 3> Jx;
    const Eigen::MatrixXd J = pixel_jacobian_wrt_parameters(r.camera, params, c.enu, &Jx);
    const Eigen::MatrixXd P = pixel_jacobian_wrt_parameters(r.camera, kPrincipalPoint, c.enu);
    const Eigen::Vector3d sd = c.sd_enu ? *c.sd_enu : Eigen::Vector3d::Constant(default_sd_m);
    const Eigen::Matrix2d C = pixel_sigma_px * pixel_sigma_px * Eigen::Matrix2d::Identity() +
                              Jx * sd.cwiseProduct(sd).asDiagonal() * Jx.transpose();
    const Eigen::Matrix2d W = C.inverse();
    F += J.transpose() * W * J;
    B += J.transpose() * W * P;
    ++used;
  }
  if (used == 0 || n == 0) return {};
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(F);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return {};
  return ldlt.solve(B);
}

}  // namespace

double principal_point_offset_bias_m(const std::vector<PrincipalPointCostCamera>& cams,
                                     const std::vector<Eigen::Vector3d>& points, double offset_px,
                                     double pixel_sigma_px, double default_sd_m) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::vector<Eigen::MatrixXd> G(cams.size());
  bool any_fixed = false;
  for (std::size_t c = 0; c < cams.size(); ++c) {
    if (!holds_principal_point_fixed(*cams[c].calibration)) continue;
    any_fixed = true;
    G[c] = absorption(*cams[c].calibration, *cams[c].pairs, pixel_sigma_px, default_sd_m);
    if (G[c].size() == 0) return kNaN;
  }
  if (!any_fixed) return 0;
  double sum = 0;
  int n = 0;
  for (const Eigen::Vector3d& X : points) {
    struct View {
      std::size_t camera;
      Eigen::Matrix<double, 2, 3> Jx;
      Eigen::Matrix2d E;  // pixel error per unit shift along u and v: K·G − P
    };
    std::vector<View> views;
    Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
    for (std::size_t c = 0; c < cams.size(); ++c) {
      const Camera& cam = cams[c].calibration->camera;
      Eigen::Vector2d uv;
      if (!(world_to_camera(cam.pose, X).z() > 0) || !project(cam, X, &uv) || !inside_image(cam.intr, uv))
        continue;
      View v{c, {}, Eigen::Matrix2d::Zero()};
      const Eigen::MatrixXd K =
          pixel_jacobian_wrt_parameters(cam, propagated(*cams[c].calibration), X, &v.Jx);
      if (G[c].size() > 0) v.E = K * G[c] - pixel_jacobian_wrt_parameters(cam, kPrincipalPoint, X);
      N += v.Jx.transpose() * v.Jx;
      views.push_back(v);
    }
    if (views.size() < 2) continue;
    const Eigen::Matrix3d Ninv = N.ldlt().solve(Eigen::Matrix3d::Identity());
    for (const View& v : views) {
      const Eigen::Matrix<double, 3, 2> dX = Ninv * v.Jx.transpose() * v.E * offset_px;
      sum += 0.5 * dX.squaredNorm();  // ½(|δX(d·ê_u)|² + |δX(d·ê_v)|²)
    }
    ++n;
  }
  return n > 0 ? std::sqrt(sum / n) : kNaN;
}

}  // namespace rangecal
