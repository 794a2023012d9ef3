#include "optim/bundle/whitening.hpp"

#include <ceres/jet.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace rangecal {

Eigen::Matrix<double, 2, 3> pixel_jacobian_wrt_world(const Camera& cam, const Eigen::Vector3d& Xw) {
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

Eigen::Matrix2d whitening_matrix(const Camera& cam, const BundleObservation& o, double sigma_px) {
  const Eigen::Matrix<double, 2, 3> JX = pixel_jacobian_wrt_world(cam, o.world);
  const Eigen::Matrix2d C =
      sigma_px * sigma_px * Eigen::Matrix2d::Identity() + JX * o.world_cov * JX.transpose();
  const Eigen::Matrix2d L = C.llt().matrixL();
  return L.inverse();
}

std::vector<Eigen::Matrix2d> whitening_matrices(const Camera& cam, const std::vector<BundleObservation>& obs,
                                                double default_sigma_px) {
  std::vector<Eigen::Matrix2d> W;
  W.reserve(obs.size());
  for (const BundleObservation& o : obs)
    W.push_back(whitening_matrix(cam, o, o.pixel_sigma_px > 0 ? o.pixel_sigma_px : default_sigma_px));
  return W;
}

}  // namespace rangecal
