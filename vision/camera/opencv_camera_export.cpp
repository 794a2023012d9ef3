#include "vision/camera/opencv_camera_export.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "config/atomic_file.hpp"
#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "config/opencv_yaml.hpp"
#include "config/xml_tree.hpp"

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

// The values of the matrix `key`, which must hold one of `counts` single-channel elements.
std::vector<double> matrix_values(const OpenCvYamlDocument& doc, const char* key,
                                  std::initializer_list<std::size_t> counts, const std::string& form) {
  const OpenCvYamlEntry* e = doc.find(key);
  if (!e) throw_input_error(doc.file, 0, key, "missing; expected " + form);
  if (e->kind != OpenCvYamlEntry::Kind::matrix)
    throw_input_error(doc.file, e->line, key, "not a matrix (rows, cols, dt, data); expected " + form);
  if (e->channels != 1)
    throw_input_error(doc.file, e->line, key,
                      "has " + std::to_string(e->channels) + " channels per element; expected " + form);
  if (std::find(counts.begin(), counts.end(), e->data.size()) == counts.end())
    throw_input_error(
        doc.file, e->line, key,
        "has " + std::to_string(e->rows) + "x" + std::to_string(e->cols) + " elements; expected " + form);
  for (const double v : e->data)
    if (!std::isfinite(v)) throw_input_error(doc.file, e->data_line, key, "contains a non-finite value");
  return e->data;
}

// A scalar entry `key` as text; nullptr when the key is absent.
const std::string* scalar_text(const OpenCvYamlDocument& doc, const char* key, const std::string& form) {
  const OpenCvYamlEntry* e = doc.find(key);
  if (!e) return nullptr;
  if (e->kind != OpenCvYamlEntry::Kind::scalar)
    throw_input_error(doc.file, e->line, key, "not a single value; expected " + form);
  return &e->scalar;
}

int read_pixels(const OpenCvYamlDocument& doc, const char* key) {
  const std::string* text = scalar_text(doc, key, "pixels");
  if (!text) throw_input_error(doc.file, 0, key, "missing; expected a positive number of pixels");
  const auto v = parse_int64(*text);
  if (!v || *v < 1 || *v > std::numeric_limits<int>::max())
    throw_input_error(doc.file, doc.find(key)->line, key,
                      "expected a positive number of pixels, got '" + printable_excerpt(*text) + "'");
  return static_cast<int>(*v);
}

// An optional real (the fit report): absent leaves *out as it is; present must be a number.
void read_optional_real(const OpenCvYamlDocument& doc, const char* key, double* out) {
  const std::string* text = scalar_text(doc, key, "a number");
  if (text && !parse_opencv_yaml_real(*text, out))
    throw_input_error(doc.file, doc.find(key)->line, key,
                      "'" + printable_excerpt(*text) + "' is not a number");
}

void read_optional_int(const OpenCvYamlDocument& doc, const char* key, int* out) {
  const std::string* text = scalar_text(doc, key, "an integer");
  if (!text) return;
  const auto v = parse_int64(*text);
  if (!v || *v < 0 || *v > std::numeric_limits<int>::max())
    throw_input_error(doc.file, doc.find(key)->line, key,
                      "'" + printable_excerpt(*text) + "' is not a non-negative integer");
  *out = static_cast<int>(*v);
}

}  // namespace

OpenCvCamera read_opencv_camera_yml(const std::string& path) {
  // Read by rangecal's own reader of OpenCV's YAML, not by cv::FileStorage: OpenCV 4.6's parser
  // can hang or overflow its stack on a damaged file (config/opencv_yaml.hpp).
  const OpenCvYamlDocument doc = read_opencv_yaml_file(path);
  OpenCvCamera oc;
  oc.image_width = read_pixels(doc, "image_width");
  oc.image_height = read_pixels(doc, "image_height");
  const std::vector<double> K = matrix_values(doc, "camera_matrix", {9}, "a 3x3 camera matrix");
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) oc.camera_matrix(i, k) = K[static_cast<std::size_t>(i * 3 + k)];
  const OpenCvYamlEntry* de = doc.find("distortion_coefficients");
  if (de && de->kind == OpenCvYamlEntry::Kind::matrix && de->channels == 1 && de->data.size() == 14)
    throw_input_error(path, de->line, "distortion_coefficients",
                      "tilted-sensor terms (14 coefficients) are not supported; expected 4, 5, 8 or 12");
  oc.distortion_coefficients = matrix_values(doc, "distortion_coefficients", {4, 5, 8, 12},
                                             "4, 5, 8 or 12 coefficients (OpenCV's layouts)");
  const std::vector<double> r = matrix_values(doc, "rvec", {3}, "a 3-element Rodrigues vector");
  const std::vector<double> t = matrix_values(doc, "tvec", {3}, "a 3-element translation (m)");
  for (int i = 0; i < 3; ++i) {
    oc.rvec[i] = r[static_cast<std::size_t>(i)];
    oc.tvec[i] = t[static_cast<std::size_t>(i)];
  }
  read_optional_real(doc, "fit_max_error_px", &oc.fit_max_px);
  read_optional_real(doc, "fit_rms_error_px", &oc.fit_rms_px);
  read_optional_int(doc, "fit_points", &oc.fit_points);
  read_optional_real(doc, "undistort_points_max_error_px", &oc.undistort_max_px);
  read_optional_real(doc, "undistort_points_rms_error_px", &oc.undistort_rms_px);
  read_optional_int(doc, "undistort_points_iterations", &oc.undistort_iterations);
  return oc;
}

}  // namespace rangecal
