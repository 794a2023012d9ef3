#include "optim/network/network_input_checks.hpp"

#include <Eigen/Cholesky>

#include "config/error.hpp"
#include "optim/bundle/bundle_input_checks.hpp"
#include "optim/network/network_parameters.hpp"

namespace rangecal {

std::vector<BundleObservation> camera_bundle_observations(
    std::size_t camera, const std::vector<NetworkPoint>& points,
    const std::vector<NetworkObservation>& observations) {
  std::vector<BundleObservation> out;
  for (const NetworkObservation& o : observations) {
    if (o.camera != camera) continue;
    BundleObservation b;
    b.world = points[o.point].prior_enu + o.offset_m;
    b.world_cov = points[o.point].prior_cov;
    b.pixel = o.pixel;
    b.pixel_sigma_px = o.pixel_sigma_px;
    b.velocity = o.velocity;
    b.source = o.source;
    out.push_back(b);
  }
  return out;
}

void check_network_input(const std::vector<NetworkCamera>& cameras, const std::vector<NetworkPoint>& points,
                         const std::vector<NetworkObservation>& observations) {
  if (cameras.empty()) throw_calibration_error("network", "no cameras");
  for (std::size_t k = 0; k < points.size(); ++k) {
    const NetworkPoint& p = points[k];
    auto at = [&] { return p.source.empty() ? "point " + std::to_string(k + 1) : p.source; };
    if (!p.prior_enu.allFinite()) throw_calibration_error(at() + ".prior", "E, N, U must be finite");
    const Eigen::LLT<Eigen::Matrix3d> llt(p.prior_cov);
    if (!p.prior_cov.allFinite() || llt.info() != Eigen::Success || !(p.prior_cov.diagonal().minCoeff() > 0))
      throw_calibration_error(at() + ".covariance",
                              "the prior covariance must be finite and positive definite");
  }
  for (std::size_t i = 0; i < observations.size(); ++i) {
    const NetworkObservation& o = observations[i];
    auto at = [&] { return o.source.empty() ? "observation " + std::to_string(i + 1) : o.source; };
    if (o.camera >= cameras.size())
      throw_calibration_error(
          at(), "refers to camera " + std::to_string(o.camera) + " of " + std::to_string(cameras.size()));
    if (o.point >= points.size())
      throw_calibration_error(
          at(), "refers to point " + std::to_string(o.point) + " of " + std::to_string(points.size()));
    if (!o.offset_m.allFinite())
      throw_calibration_error(at() + ".offset", "must be finite (got NaN or infinity)");
  }
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    const BundleSetup setup = bundle_setup(cameras[c].options);
    const Camera start = bundle_starting_camera(cameras[c].initial, setup, cameras[c].options);
    check_bundle_input(start, camera_bundle_observations(c, points, observations), setup, cameras[c].options);
  }
}

}  // namespace rangecal
