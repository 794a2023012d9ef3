#include "vision/camera/opencv_camera_export.hpp"

#include <ceres/ceres.h>

#include <cmath>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "config/atomic_file.hpp"
#include "config/error.hpp"

namespace rangecal {
namespace {

// OpenCV's forward model (see the header). a = fx, fy, cx, cy, k1, k2, p1, p2, k3;
// b = k4, k5, k6 (rational), s1, s2, s3, s4 (thin prism).
template <typename T>
void opencv_forward(const T* a, const T* b, const T& x, const T& y, T* u, T* v) {
  const T r2 = x * x + y * y;
  const T num = T(1) + a[4] * r2 + a[5] * r2 * r2 + a[8] * r2 * r2 * r2;
  const T den = T(1) + b[0] * r2 + b[1] * r2 * r2 + b[2] * r2 * r2 * r2;
  const T radial = num / den;
  const T xd = x * radial + T(2) * a[6] * x * y + a[7] * (r2 + T(2) * x * x) + b[3] * r2 + b[4] * r2 * r2;
  const T yd = y * radial + a[6] * (r2 + T(2) * y * y) + T(2) * a[7] * x * y + b[5] * r2 + b[6] * r2 * r2;
  *u = a[0] * xd + a[2];
  *v = a[1] * yd + a[3];
}

struct GridPoint {
  double x, y;  // rangecal's undistorted normalised coordinates of the pixel (x'/z', y'/z')
  double u, v;  // the pixel
};

struct FitResidual {
  GridPoint p;
  template <typename T>
  bool operator()(const T* a, const T* rational, const T* prism, T* r) const {
    const T b[7] = {rational[0], rational[1], rational[2], prism[0], prism[1], prism[2], prism[3]};
    T u, v;
    opencv_forward(a, b, T(p.x), T(p.y), &u, &v);
    r[0] = u - T(p.u);
    r[1] = v - T(p.v);
    return true;
  }
};

// nu × nv pixels spread evenly over the image area [−0.5, W − 0.5] × [−0.5, H − 0.5] (pixel
// centres at integers), each with its exact undistorted normalised coordinates (closed form).
std::vector<GridPoint> make_grid(const Camera& cam, int nu, int nv, double offset) {
  const CameraIntrinsics& in = cam.intr;
  std::vector<GridPoint> g;
  g.reserve(static_cast<std::size_t>(nu) * nv);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double fu = std::min(1.0, (i + offset) / (nu - 1)), fv = std::min(1.0, (j + offset) / (nv - 1));
      const Eigen::Vector2d uv(-0.5 + fu * in.width_px, -0.5 + fv * in.height_px);
      const Eigen::Vector2d s = pixel_to_undistorted_sensor(in, uv);
      g.push_back({s.x() / in.f_mm, s.y() / in.f_mm, uv.x(), uv.y()});
    }
  return g;
}

void evaluate(const double* a, const double* b, const std::vector<GridPoint>& grid, double* max_px,
              double* rms_px) {
  double mx = 0, ss = 0;
  for (const auto& p : grid) {
    double u, v;
    opencv_forward(a, b, p.x, p.y, &u, &v);
    const double e = std::hypot(u - p.u, v - p.v);
    mx = std::max(mx, e);
    ss += e * e;
  }
  *max_px = mx;
  *rms_px = std::sqrt(ss / grid.size());
}

// Fits the first n_coeffs of OpenCV's distortion vector (5, 8 or 12) plus fx, fy, cx, cy; the
// other coefficients stay as they are in b.
void solve(const std::vector<GridPoint>& grid, double* a, double* b, int n_coeffs) {
  ceres::Problem problem;
  for (const auto& p : grid)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<FitResidual, 2, 9, 3, 4>(new FitResidual{p}),
                             nullptr, a, b, b + 3);
  if (n_coeffs < 8) problem.SetParameterBlockConstant(b);
  if (n_coeffs < 12) problem.SetParameterBlockConstant(b + 3);
  ceres::Solver::Options opt;
  opt.linear_solver_type = ceres::DENSE_QR;
  opt.max_num_iterations = 500;
  opt.function_tolerance = 1e-16;
  opt.gradient_tolerance = 1e-20;
  opt.parameter_tolerance = 1e-16;
  opt.num_threads = 1;  // deterministic
  opt.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(opt, &problem, &summary);
}

}  // namespace

OpenCvCamera fit_opencv_camera(const Camera& cam, double tolerance_px) {
  const CameraIntrinsics& in = cam.intr;
  if (in.width_px < 2 || in.height_px < 2 || !(in.f_mm > 0) || !(in.dx_mm > 0) || !(in.dy_mm > 0) ||
      !(in.sx > 0))
    throw_calibration_error(
        "OpenCV export", "camera '" + cam.id + "' has no valid image size, focal length, pixel pitch or sx");
  // Fit on a 65 × 41 grid; measure on a 129 × 81 grid offset by half a step (so the evaluation
  // points are mostly not fit points), plus the image corners.
  const std::vector<GridPoint> fit_grid = make_grid(cam, 65, 41, 0.0);
  std::vector<GridPoint> eval_grid = make_grid(cam, 129, 81, 0.5);
  const std::vector<GridPoint> corners = make_grid(cam, 2, 2, 0.0);
  eval_grid.insert(eval_grid.end(), corners.begin(), corners.end());

  // Start from the first-order inverse of the radial term: rd = ru (1 − k1 ru² + 3 k1² ru⁴ − 12 k1³ ru⁶ …),
  // with ru = f·r' in mm, so OpenCV's k1 ≈ −k1·f², k2 ≈ 3 k1² f⁴, k3 ≈ −12 k1³ f⁶.
  const double f = in.f_mm, k1 = in.dist.k1, f2 = f * f;
  double a[9] = {f * in.sx / in.dx_mm,
                 f / in.dy_mm,
                 in.u0_px,
                 in.v0_px,
                 -k1 * f2,
                 3 * k1 * k1 * f2 * f2,
                 0,
                 0,
                 -12 * k1 * k1 * k1 * f2 * f2 * f2};
  double b[7] = {0, 0, 0, 0, 0, 0, 0};
  solve(fit_grid, a, b, 5);
  double mx, rms;
  evaluate(a, b, eval_grid, &mx, &rms);
  int n_coeffs = 5;
  // Richer OpenCV layouts only when needed: 8 (rational: strong radial distortion), then 12 (thin
  // prism: absorbs the radial × tangential cross terms that inverting seed 000 eq. 7 produces).
  for (const int n : {8, 12}) {
    if (mx <= tolerance_px) break;
    double a2[9], b2[7], mx2, rms2;
    std::copy(a, a + 9, a2);
    std::copy(b, b + 7, b2);
    solve(fit_grid, a2, b2, n);
    evaluate(a2, b2, eval_grid, &mx2, &rms2);
    if (mx2 < mx) {
      std::copy(a2, a2 + 9, a);
      std::copy(b2, b2 + 7, b);
      mx = mx2;
      rms = rms2;
      n_coeffs = n;
    }
  }

  OpenCvCamera oc;
  oc.image_width = in.width_px;
  oc.image_height = in.height_px;
  oc.camera_matrix << a[0], 0, a[2], 0, a[1], a[3], 0, 0, 1;
  oc.distortion_coefficients = {a[4], a[5], a[6], a[7], a[8]};
  oc.distortion_coefficients.insert(oc.distortion_coefficients.end(), b, b + (n_coeffs - 5));
  cv::Matx33d R;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) R(i, k) = cam.pose.R(i, k);
  cv::Vec3d rvec;
  cv::Rodrigues(R, rvec);
  oc.rvec = Eigen::Vector3d(rvec[0], rvec[1], rvec[2]);
  oc.tvec = cam.pose.T;
  oc.fit_max_px = mx;
  oc.fit_rms_px = rms;
  oc.fit_points = static_cast<int>(eval_grid.size());
  return oc;
}

Eigen::Vector2d project_opencv(const OpenCvCamera& oc, const Eigen::Vector3d& Xw) {
  cv::Vec3d rvec(oc.rvec.x(), oc.rvec.y(), oc.rvec.z());
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d Re;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) Re(i, k) = R(i, k);
  const Eigen::Vector3d xc = Re * Xw + oc.tvec;
  const auto& K = oc.camera_matrix;
  const auto& d = oc.distortion_coefficients;
  const double a[9] = {
      K(0, 0), K(1, 1), K(0, 2), K(1, 2), d.at(0), d.at(1), d.at(2), d.at(3), d.size() > 4 ? d[4] : 0};
  double b[7] = {0, 0, 0, 0, 0, 0, 0};
  for (std::size_t i = 5; i < std::min<std::size_t>(d.size(), 12); ++i) b[i - 5] = d[i];
  double u, v;
  opencv_forward(a, b, xc.x() / xc.z(), xc.y() / xc.z(), &u, &v);
  return {u, v};
}

std::string opencv_camera_yml_text(const OpenCvCamera& oc) {
  cv::FileStorage fs(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
  fs << "image_width" << oc.image_width;
  fs << "image_height" << oc.image_height;
  cv::Mat K(3, 3, CV_64F);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) K.at<double>(i, k) = oc.camera_matrix(i, k);
  fs << "camera_matrix" << K;
  cv::Mat d(1, static_cast<int>(oc.distortion_coefficients.size()), CV_64F);
  for (std::size_t i = 0; i < oc.distortion_coefficients.size(); ++i)
    d.at<double>(0, static_cast<int>(i)) = oc.distortion_coefficients[i];
  fs << "distortion_coefficients" << d;
  cv::Mat r(3, 1, CV_64F), t(3, 1, CV_64F);
  for (int i = 0; i < 3; ++i) {
    r.at<double>(i) = oc.rvec[i];
    t.at<double>(i) = oc.tvec[i];
  }
  fs << "rvec" << r;
  fs << "tvec" << t;
  fs << "fit_max_error_px" << oc.fit_max_px;
  fs << "fit_rms_error_px" << oc.fit_rms_px;
  fs << "fit_points" << oc.fit_points;
  return fs.releaseAndGetString();
}

void write_opencv_camera_yml(const std::string& path, const OpenCvCamera& oc) {
  write_file_atomic(path, opencv_camera_yml_text(oc));
}

namespace {

cv::Mat read_matrix(const cv::FileStorage& fs, const std::string& path, const char* key, int rows, int cols,
                    const std::string& form) {
  const cv::FileNode n = fs[key];
  if (n.empty()) throw_input_error(path, 0, key, "missing; expected " + form);
  // OpenCV allocates rows × cols × element size as the file states before it reads the data, so a
  // one-byte edit of `rows` could ask for gigabytes: the shape is checked against the data first
  // (the matrices here have at most 14 elements).
  const cv::FileNode nr = n.isMap() ? n["rows"] : cv::FileNode(), nc = n.isMap() ? n["cols"] : cv::FileNode(),
                     nd = n.isMap() ? n["data"] : cv::FileNode();
  if (!nr.isInt() || !nc.isInt() || !nd.isSeq() || static_cast<int>(nr) < 1 || static_cast<int>(nc) < 1 ||
      static_cast<int>(nr) > 64 || static_cast<int>(nc) > 64 ||
      nd.size() != static_cast<std::size_t>(static_cast<int>(nr) * static_cast<int>(nc)))
    throw_input_error(
        path, 0, key,
        "not a matrix (rows and cols of 1 to 64 and rows × cols data values); expected " + form);
  cv::Mat m;
  try {
    n >> m;
  } catch (const cv::Exception&) {
    throw_input_error(path, 0, key, "not a matrix; expected " + form);
  }
  if (m.empty()) throw_input_error(path, 0, key, "not a matrix; expected " + form);
  m.convertTo(m, CV_64F);
  if (rows > 0 && (m.rows * m.cols != rows * cols))
    throw_input_error(
        path, 0, key,
        "has " + std::to_string(m.rows) + "x" + std::to_string(m.cols) + " elements; expected " + form);
  for (int i = 0; i < m.rows * m.cols; ++i)
    if (!std::isfinite(m.at<double>(i))) throw_input_error(path, 0, key, "contains a non-finite value");
  return m;
}

int read_int(const cv::FileStorage& fs, const std::string& path, const char* key) {
  const cv::FileNode n = fs[key];
  if (n.empty() || !n.isInt()) throw_input_error(path, 0, key, "missing or not an integer; expected pixels");
  const int v = static_cast<int>(n);
  if (v < 1)
    throw_input_error(path, 0, key, "expected a positive number of pixels, got " + std::to_string(v));
  return v;
}

}  // namespace

OpenCvCamera read_opencv_camera_yml(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw_input_error(path, 0, "", "file not found");
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ);
  } catch (const cv::Exception& e) {
    throw_input_error(path, 0, "", std::string("not a readable OpenCV FileStorage file: ") + e.err);
  } catch (const std::exception& e) {
    // OpenCV 4.6's YAML parser can also fail with a standard exception (std::length_error on a
    // damaged line, found by fuzzing).
    throw_input_error(path, 0, "", std::string("not a readable OpenCV FileStorage file: ") + e.what());
  }
  if (!fs.isOpened()) throw_input_error(path, 0, "", "not a readable OpenCV FileStorage file");
  // Looking a key up in a document whose top level is a list or a value is an OpenCV assertion
  // (cv::Exception), so the top level is checked first.
  if (!fs.root().isMap())
    throw_input_error(path, 0, "", "the top level is not a map of keys (image_width, camera_matrix, ...)");
  OpenCvCamera oc;
  oc.image_width = read_int(fs, path, "image_width");
  oc.image_height = read_int(fs, path, "image_height");
  const cv::Mat K = read_matrix(fs, path, "camera_matrix", 3, 3, "a 3x3 camera matrix");
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) oc.camera_matrix(i, k) = K.at<double>(i * 3 + k);
  const cv::Mat d = read_matrix(fs, path, "distortion_coefficients", 0, 0, "4, 5, 8, 12 or 14 coefficients");
  const int nd = d.rows * d.cols;
  if (nd != 4 && nd != 5 && nd != 8 && nd != 12 && nd != 14)
    throw_input_error(
        path, 0, "distortion_coefficients",
        "has " + std::to_string(nd) + " elements; expected 4, 5, 8, 12 or 14 (OpenCV's layouts)");
  if (nd > 12)
    throw_input_error(path, 0, "distortion_coefficients",
                      "tilted-sensor terms (14 coefficients) are not supported; expected 4, 5, 8 or 12");
  for (int i = 0; i < nd; ++i) oc.distortion_coefficients.push_back(d.at<double>(i));
  const cv::Mat r = read_matrix(fs, path, "rvec", 3, 1, "a 3-element Rodrigues vector");
  const cv::Mat t = read_matrix(fs, path, "tvec", 3, 1, "a 3-element translation (m)");
  for (int i = 0; i < 3; ++i) {
    oc.rvec[i] = r.at<double>(i);
    oc.tvec[i] = t.at<double>(i);
  }
  if (const cv::FileNode n = fs["fit_max_error_px"]; n.isReal()) oc.fit_max_px = static_cast<double>(n);
  if (const cv::FileNode n = fs["fit_rms_error_px"]; n.isReal()) oc.fit_rms_px = static_cast<double>(n);
  if (const cv::FileNode n = fs["fit_points"]; n.isInt()) oc.fit_points = static_cast<int>(n);
  return oc;
}

}  // namespace rangecal
