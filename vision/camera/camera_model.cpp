#include "vision/camera/camera_model.hpp"

namespace rangecal {

bool project(const Camera& cam, const Eigen::Vector3d& Xw, Eigen::Vector2d* uv) {
  const Eigen::Vector3d xc = world_to_camera(cam.pose, Xw);
  const double intr[4] = {cam.intr.f_mm, cam.intr.sx, cam.intr.u0_px, cam.intr.v0_px};
  const auto d = cam.intr.dist.as_array();
  double u = 0, v = 0;
  const bool ok = project_camera_point(intr, d.data(), cam.intr.dx_mm, cam.intr.dy_mm, xc.data(), &u, &v);
  *uv = {u, v};
  return ok;
}

Eigen::Vector2d pixel_to_undistorted_sensor(const CameraIntrinsics& in, const Eigen::Vector2d& uv) {
  double xd, yd, xu, yu;
  pixel_to_sensor(in.sx, in.u0_px, in.v0_px, in.dx_mm, in.dy_mm, uv.x(), uv.y(), &xd, &yd);
  const auto d = in.dist.as_array();
  undistort_sensor(d.data(), xd, yd, &xu, &yu);
  return {xu, yu};
}

Eigen::Vector3d pixel_ray_world(const Camera& cam, const Eigen::Vector2d& uv) {
  const Eigen::Vector2d s = pixel_to_undistorted_sensor(cam.intr, uv);
  const Eigen::Vector3d ray_cam(s.x(), s.y(), cam.intr.f_mm);
  return (cam.pose.R.transpose() * ray_cam).normalized();
}

}  // namespace rangecal
