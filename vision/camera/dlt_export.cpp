#include "vision/camera/dlt_export.hpp"

#include <algorithm>
#include <cmath>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "vision/camera/opencv_distortion_fit.hpp"

namespace rangecal {
namespace {

/// rangecal's samples (pixel, ray in x right / y down axes) in the tools' frame (y up).
std::vector<DistortionSample> in_dlt_frame(std::vector<DistortionSample> samples, int height_px) {
  for (DistortionSample& s : samples) {
    s.pixel = to_dlt_pixel(s.pixel, height_px);
    s.normalised.y() = -s.normalised.y();
  }
  return samples;
}

}  // namespace

Eigen::Vector2d to_dlt_pixel(const Eigen::Vector2d& uv, int height_px) {
  return {uv.x() + 0.5, height_px - 0.5 - uv.y()};
}

Eigen::Vector2d from_dlt_pixel(const Eigen::Vector2d& xy, int height_px) {
  return {xy.x() - 0.5, height_px - 0.5 - xy.y()};
}

DltCamera dlt_camera(const Camera& cam) {
  const CameraIntrinsics& in = cam.intr;
  if (in.width_px < 2 || in.height_px < 2 || !(in.f_mm > 0) || !(in.dx_mm > 0) || !(in.dy_mm > 0) ||
      !(in.sx > 0))
    throw_calibration_error(
        "DLT export", "camera '" + cam.id + "' has no valid image size, focal length, pixel pitch or sx");
  const int H = in.height_px;
  const std::vector<DistortionSample> fit = in_dlt_frame(image_grid_samples(cam, 33, 21, 0.0), H);
  std::vector<DistortionSample> eval = in_dlt_frame(image_grid_samples(cam, 129, 81, 0.5), H);
  const std::vector<DistortionSample> corners = in_dlt_frame(image_grid_samples(cam, 2, 2, 0.0), H);
  eval.insert(eval.end(), corners.begin(), corners.end());

  // Start from the series inverse of the radial term (as vision/camera/opencv_camera_export.cpp).
  const double f = in.f_mm, k1 = in.dist.k1, f2 = f * f;
  OpenCvDistortionModel start;
  start.fx = start.fy = f / in.dy_mm;
  start.cx = in.u0_px + 0.5;
  start.cy = H - 0.5 - in.v0_px;
  start.coefficients = {-k1 * f2, 3 * k1 * k1 * f2 * f2, 0, 0, -12 * k1 * k1 * k1 * f2 * f2 * f2};
  OpenCvFitOptions options;
  options.layouts = {5};  // Argus' pinhole profile has k1 k2 t1 t2 k3 only
  options.equal_focal = true;
  options.free_affine = true;
  options.minimax_rounds = 6;  // the 5-term profile's error is set by its worst corner
  const OpenCvFit pf = fit_opencv_distortion(fit, eval, start, options);

  DltCamera d;
  d.id = cam.id;
  d.width_px = in.width_px;
  d.height_px = H;
  d.f_px = pf.model.fx;
  d.cx_px = pf.model.cx;
  d.cy_px = pf.model.cy;
  for (int i = 0; i < 5; ++i) d.k[i] = pf.model.coefficients[i];
  d.profile_max_px = pf.project_max_px;
  d.profile_rms_px = pf.project_rms_px;
  d.undistort_max_px = pf.undistort_max_px;
  d.undistort_rms_px = pf.undistort_rms_px;
  d.points = pf.points;

  // P = K·A·F·[R | T]: the undistorted tools' pixel of a world point (the profile's inverse).
  Eigen::Matrix3d K, A = Eigen::Matrix3d::Identity(), F = Eigen::Vector3d(1, -1, 1).asDiagonal();
  K << d.f_px, 0, d.cx_px, 0, d.f_px, d.cy_px, 0, 0, 1;
  A.topLeftCorner<2, 2>() = pf.affine;
  Eigen::Matrix<double, 3, 4> Rt;
  Rt << cam.pose.R, cam.pose.T;
  const Eigen::Matrix<double, 3, 4> P = K * A * F * Rt;
  // P₃₄ = Tz, the depth of the world origin; DLT-11 fixes it to 1, impossible when it is 0.
  if (!(std::abs(P(2, 3)) > 1e-6 * std::max(1.0, cam.pose.T.norm())))
    throw_calibration_error("DLT export", "camera '" + cam.id +
                                              "': the world origin lies in the camera's principal plane "
                                              "(Tz = 0), so its DLT-11 coefficients are undefined");
  const Eigen::Matrix<double, 3, 4> L = P / P(2, 3);
  for (int i = 0; i < 4; ++i) {
    d.L[i] = L(0, i);
    d.L[4 + i] = L(1, i);
  }
  for (int i = 0; i < 3; ++i) d.L[8 + i] = L(2, i);

  // The DLT alone: the undistorted pixel of each sample's ray against its (distorted) pixel.
  double ss = 0;
  for (const DistortionSample& s : eval) {
    const Eigen::Vector2d xa = pf.affine * s.normalised;
    const double e = (Eigen::Vector2d(d.f_px * xa.x() + d.cx_px, d.f_px * xa.y() + d.cy_px) - s.pixel).norm();
    d.dlt_only_max_px = std::max(d.dlt_only_max_px, e);
    ss += e * e;
  }
  d.dlt_only_rms_px = std::sqrt(ss / eval.size());
  return d;
}

std::string dlt_coefficients_csv(const std::vector<DltCamera>& cameras) {
  std::string s;
  for (int i = 0; i < 11; ++i) {
    for (std::size_t c = 0; c < cameras.size(); ++c)
      s += (c ? "," : "") + format_number("%.15g", cameras[c].L[i]);
    s += "\n";
  }
  return s;
}

std::string argus_profile_txt(const std::vector<DltCamera>& cameras) {
  std::string s;
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    const DltCamera& d = cameras[c];
    const auto g = [](double x) { return " " + format_number("%.15g", x); };
    s += std::to_string(c + 1) + g(d.f_px) + " " + std::to_string(d.width_px) + " " +
         std::to_string(d.height_px) + g(d.cx_px) + g(d.cy_px) + " 1" + g(d.k[0]) + g(d.k[1]) + g(d.k[2]) +
         g(d.k[3]) + g(d.k[4]) + "\n";
  }
  return s;
}

}  // namespace rangecal
