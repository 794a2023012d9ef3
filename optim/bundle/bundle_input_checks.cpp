#include "optim/bundle/bundle_input_checks.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "config/error.hpp"

namespace rangecal {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;

void check_bundle_input(const Camera& cam, const std::vector<BundleObservation>& obs,
                        const BundleSetup& setup, const BundleOptions& opt) {
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
  if (setup.principal_point_prior &&
      !(opt.priors.principal_point_sigma_px > 0 && opt.priors.principal_point_px.allFinite()))
    throw_calibration_error("priors.principal_point_sigma_px",
                            "the principal-point prior needs a finite value and σ > 0");
  if (setup.center_prior &&
      !((opt.priors.center_sigma_m.array() > 0).all() && opt.priors.center_enu_m.allFinite()))
    throw_calibration_error("priors.center_sigma_m",
                            "the camera-centre prior needs a finite value and σ > 0");
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const auto& o = obs[i];
    // The name is built only for an error: a string per observation is measurable at 160,000.
    const auto at = [i] { return "observation " + std::to_string(i + 1); };
    if (!o.world.allFinite())
      throw_calibration_error(at() + ".world", "E, N, U must be finite (got NaN or infinity)");
    if (!o.pixel.allFinite())
      throw_calibration_error(at() + ".pixel", "u, v must be finite (got NaN or infinity)");
    if (!o.world_cov.allFinite() || o.world_cov.diagonal().minCoeff() < 0)
      throw_calibration_error(at() + ".world_cov",
                              "the world-point covariance must be finite and non-negative");
    if (!std::isfinite(o.pixel_sigma_px)) throw_calibration_error(at() + ".pixel_sigma_px", "must be finite");
    if (!o.velocity.allFinite())
      throw_calibration_error(at() + ".velocity", "the lamp velocity must be finite (got NaN or infinity)");
  }
  if (setup.is_free(CameraParameter::clock_offset) &&
      std::none_of(obs.begin(), obs.end(),
                   [](const BundleObservation& ob) { return ob.velocity.norm() > 0; }))
    throw_calibration_error("bundle.clock_offset",
                            "the clock offset is free but no observation carries a lamp velocity "
                            "(correspondences.csv without vE,vN,vU, or a lamp that never moved): rerun the "
                            "align and detect stages, or fix clock_offset");
  const int n = static_cast<int>(obs.size());
  if (2 * n < setup.n_free)
    throw_calibration_error("bundle", "fewer observations than unknowns: " + std::to_string(n) +
                                          " points give " + std::to_string(2 * n) + " equations for " +
                                          std::to_string(setup.n_free) + " free parameters");
  const bool pose_free = std::any_of(setup.free.begin() + index_of(CameraParameter::wx), setup.free.end(),
                                     [](bool b) { return b; });
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
  std::string which;  // the first few, by where they came from
  for (int i = 0; i < n; ++i) {
    if (world_to_camera(cam.pose, obs[i].world).z() > 0) continue;
    if (++behind <= 3)
      which += (behind > 1 ? ", " : "") +
               (obs[i].source.empty() ? "point " + std::to_string(i + 1) : obs[i].source);
  }
  if (behind > 0)
    throw_calibration_error("bundle.initial",
                            std::to_string(behind) + " of " + std::to_string(n) +
                                " points are behind the initial camera (Zc ≤ 0): " + which +
                                (behind > 3 ? ", …" : "") +
                                "; a control pole behind the camera is a wrong pick or survey, else the "
                                "starting pose is wrong");
}

}  // namespace rangecal
