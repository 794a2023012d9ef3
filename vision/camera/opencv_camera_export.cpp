#include "vision/camera/opencv_camera_export.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "config/atomic_file.hpp"
#include "config/error.hpp"

namespace rangecal {

OpenCvCamera fit_opencv_camera(const Camera& cam, double tolerance_px) {
  const CameraIntrinsics& in = cam.intr;
  if (in.width_px < 2 || in.height_px < 2 || !(in.f_mm > 0) || !(in.dx_mm > 0) || !(in.dy_mm > 0) ||
      !(in.sx > 0))
    throw_calibration_error(
        "OpenCV export", "camera '" + cam.id + "' has no valid image size, focal length, pixel pitch or sx");
  // Fit on a 49 × 31 grid (the mapping is smooth);
  // measure on a 129 × 81 grid offset by half a step (so the evaluation points are mostly not fit
  // points), plus the image corners.
  const std::vector<DistortionSample> fit_grid = image_grid_samples(cam, 49, 31, 0.0);
  std::vector<DistortionSample> eval_grid = image_grid_samples(cam, 129, 81, 0.5);
  const std::vector<DistortionSample> corners = image_grid_samples(cam, 2, 2, 0.0);
  eval_grid.insert(eval_grid.end(), corners.begin(), corners.end());

  // Start from the series inverse of the radial term: rd = ru (1 − k1 ru² + 3 k1² ru⁴ − 12 k1³ ru⁶ …),
  // with ru = f·r' in mm, so OpenCV's k1 ≈ −k1·f², k2 ≈ 3 k1² f⁴, k3 ≈ −12 k1³ f⁶.
  const double f = in.f_mm, k1 = in.dist.k1, f2 = f * f;
  OpenCvDistortionModel start;
  start.fx = f * in.sx / in.dx_mm;
  start.fy = f / in.dy_mm;
  start.cx = in.u0_px;
  start.cy = in.v0_px;
  start.coefficients = {-k1 * f2, 3 * k1 * k1 * f2 * f2, 0, 0, -12 * k1 * k1 * k1 * f2 * f2 * f2};
  OpenCvFitOptions options;
  options.tolerance_px = tolerance_px;
  // Both directions together first: cv::undistortPoints' 5 default iterations leave an error set
  // by the lens (0.015 px at the corners of seed 002's 7 % distortion with an exact model), which
  // the joint fit shares between the two directions.
  OpenCvFit fit = fit_opencv_distortion(fit_grid, eval_grid, start, options);
  if (std::max(fit.project_max_px, fit.undistort_max_px) > tolerance_px) {
    // Where no model keeps both within the tolerance, cv::projectPoints is kept exact and the
    // undistortPoints error reported: more iterations (cv::undistortPointsIter) remove it.
    options.undistort_weight = 0;
    fit = fit_opencv_distortion(fit_grid, eval_grid, fit.model, options);
  }

  OpenCvCamera oc;
  oc.image_width = in.width_px;
  oc.image_height = in.height_px;
  oc.camera_matrix << fit.model.fx, 0, fit.model.cx, 0, fit.model.fy, fit.model.cy, 0, 0, 1;
  oc.distortion_coefficients = fit.model.coefficients;
  cv::Matx33d R;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) R(i, k) = cam.pose.R(i, k);
  cv::Vec3d rvec;
  cv::Rodrigues(R, rvec);
  oc.rvec = Eigen::Vector3d(rvec[0], rvec[1], rvec[2]);
  oc.tvec = cam.pose.T;
  oc.fit_max_px = fit.project_max_px;
  oc.fit_rms_px = fit.project_rms_px;
  oc.undistort_max_px = fit.undistort_max_px;
  oc.undistort_rms_px = fit.undistort_rms_px;
  oc.undistort_iterations = options.undistort_iterations;
  oc.fit_points = fit.points;
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
  return opencv_distort(opencv_distortion_model(oc), xc.head<2>() / xc.z());
}

OpenCvDistortionModel opencv_distortion_model(const OpenCvCamera& oc) {
  OpenCvDistortionModel m;
  m.fx = oc.camera_matrix(0, 0);
  m.fy = oc.camera_matrix(1, 1);
  m.cx = oc.camera_matrix(0, 2);
  m.cy = oc.camera_matrix(1, 2);
  m.coefficients = oc.distortion_coefficients;
  return m;
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
  fs << "undistort_points_max_error_px" << oc.undistort_max_px;
  fs << "undistort_points_rms_error_px" << oc.undistort_rms_px;
  fs << "undistort_points_iterations" << oc.undistort_iterations;
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
  if (const cv::FileNode n = fs["undistort_points_max_error_px"]; n.isReal())
    oc.undistort_max_px = static_cast<double>(n);
  if (const cv::FileNode n = fs["undistort_points_rms_error_px"]; n.isReal())
    oc.undistort_rms_px = static_cast<double>(n);
  if (const cv::FileNode n = fs["undistort_points_iterations"]; n.isInt())
    oc.undistort_iterations = static_cast<int>(n);
  return oc;
}

}  // namespace rangecal
