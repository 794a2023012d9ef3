#include "vision/camera/opencv_camera_import.hpp"

#include <Eigen/QR>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <vector>

#include "config/error.hpp"

namespace rangecal {
namespace {

constexpr const char* kWhat = "opencv import";

/// OpenCV's undistorted normalised coordinates (x', y') of pixels, iterated to convergence
/// (the default criteria stop after 5 iterations, far from exact at the image corners).
std::vector<cv::Point2d> opencv_undistort(const OpenCvCamera& oc, const std::vector<cv::Point2d>& px) {
  cv::Mat K;
  cv::eigen2cv(oc.camera_matrix, K);
  const cv::Mat D(oc.distortion_coefficients, true);
  std::vector<cv::Point2d> out;
  cv::undistortPoints(px, out, K, D.reshape(1, 1), cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-14));
  return out;
}

std::vector<cv::Point2d> pixel_grid(const OpenCvCamera& oc, int nu, int nv, double offset) {
  std::vector<cv::Point2d> g;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i)
      g.emplace_back((i + offset) * (oc.image_width - 1) / (nu - 1 + 2 * offset),
                     (j + offset) * (oc.image_height - 1) / (nv - 1 + 2 * offset));
  return g;
}

}  // namespace

ImportedCamera camera_from_opencv(const OpenCvCamera& oc, double dx_mm, double dy_mm) {
  const Eigen::Matrix3d& K = oc.camera_matrix;
  if (!(K(0, 0) > 0 && K(1, 1) > 0) || K(0, 1) != 0 || K(1, 0) != 0 || K(2, 0) != 0 || K(2, 1) != 0 ||
      K(2, 2) != 1)
    throw_calibration_error(kWhat, "camera_matrix is not [fx 0 cx; 0 fy cy; 0 0 1] with fx, fy > 0");
  if (!(dx_mm > 0 && dy_mm > 0)) throw_calibration_error(kWhat, "the pixel pitch must be positive");
  if (oc.image_width < 2 || oc.image_height < 2) throw_calibration_error(kWhat, "image size not set");
  const std::size_t nd = oc.distortion_coefficients.size();
  if (nd != 0 && nd != 4 && nd != 5 && nd != 8)
    throw_calibration_error(
        kWhat, "distortion_coefficients must have 4, 5 or 8 values (k1 k2 p1 p2 [k3 [k4 k5 k6]])");

  ImportedCamera res;
  CameraIntrinsics& in = res.camera.intr;
  in.width_px = oc.image_width;
  in.height_px = oc.image_height;
  in.dx_mm = dx_mm;
  in.dy_mm = dy_mm;
  in.f_mm = K(1, 1) * dy_mm;
  in.sx = K(0, 0) * dx_mm / in.f_mm;
  in.u0_px = K(0, 2);
  in.v0_px = K(1, 2);

  // Linear least squares for k1 k2 k3 p1 p2 (seed 000 eq. 7; a1 a2 stay 0: OpenCV has no shear).
  const std::vector<cv::Point2d> fit_px = pixel_grid(oc, 41, 27, 0.0);
  const std::vector<cv::Point2d> fit_n = opencv_undistort(oc, fit_px);
  Eigen::MatrixXd A(2 * fit_px.size(), 5);
  Eigen::VectorXd b(2 * fit_px.size());
  for (std::size_t i = 0; i < fit_px.size(); ++i) {
    const double xd = (fit_px[i].x - in.u0_px) * dx_mm / in.sx, yd = (fit_px[i].y - in.v0_px) * dy_mm;
    const double xu = in.f_mm * fit_n[i].x, yu = in.f_mm * fit_n[i].y;
    const double r2 = xd * xd + yd * yd;
    A.row(2 * i) << xd * r2, xd * r2 * r2, xd * r2 * r2 * r2, r2 + 2 * xd * xd, 2 * xd * yd;
    A.row(2 * i + 1) << yd * r2, yd * r2 * r2, yd * r2 * r2 * r2, 2 * xd * yd, r2 + 2 * yd * yd;
    b(2 * i) = xu - xd;
    b(2 * i + 1) = yu - yd;
  }
  if (!A.allFinite() || !b.allFinite())
    throw_calibration_error(kWhat, "OpenCV's distortion cannot be inverted over the whole image");
  // Columns span r² … r⁷ in mm: scale them to unit norm so the solve is well conditioned.
  const Eigen::VectorXd scale = A.colwise().norm().cwiseMax(1e-300).cwiseInverse();
  const Eigen::VectorXd c = (A * scale.asDiagonal()).colPivHouseholderQr().solve(b).cwiseProduct(scale);
  in.dist.k1 = c[0], in.dist.k2 = c[1], in.dist.k3 = c[2], in.dist.p1 = c[3], in.dist.p2 = c[4];

  cv::Mat rv, R;
  cv::eigen2cv(oc.rvec, rv);
  cv::Rodrigues(rv, R);
  cv::cv2eigen(R, res.camera.pose.R);
  res.camera.pose.T = oc.tvec;

  // Fit error on a denser grid offset from the fitting one: project OpenCV's ray of each pixel
  // with rangecal's model and compare with the pixel.
  const std::vector<cv::Point2d> ev_px = pixel_grid(oc, 64, 40, 0.37);
  const std::vector<cv::Point2d> ev_n = opencv_undistort(oc, ev_px);
  const double intr[4] = {in.f_mm, in.sx, in.u0_px, in.v0_px};
  const std::array<double, 7> d = in.dist.as_array();
  double sum2 = 0, mx = 0;
  for (std::size_t i = 0; i < ev_px.size(); ++i) {
    const double xc[3] = {ev_n[i].x, ev_n[i].y, 1.0};
    double u = 0, v = 0;
    double e = std::numeric_limits<double>::infinity();
    if (project_camera_point(intr, d.data(), dx_mm, dy_mm, xc, &u, &v))
      e = std::hypot(u - ev_px[i].x, v - ev_px[i].y);
    sum2 += e * e;
    mx = std::max(mx, e);
  }
  res.fit_points = static_cast<int>(ev_px.size());
  res.fit_max_px = mx;
  res.fit_rms_px = std::sqrt(sum2 / res.fit_points);
  if (!std::isfinite(mx))
    throw_calibration_error(kWhat, "rangecal's model cannot reproduce OpenCV's distortion over the image");
  return res;
}

}  // namespace rangecal
