#include "vision/calibration/dlt_camera_import.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "config/csv_table.hpp"
#include "config/error.hpp"
#include "vision/calibration/dlt.hpp"

namespace rangecal {
namespace {

constexpr const char* kDltImportWhat = "DLT import";

}  // namespace

ImportedCamera camera_from_dlt(const std::array<double, 11>& L, const SensorGeometry& sensor,
                               double* skew_px) {
  for (double l : L)
    if (!std::isfinite(l)) throw_calibration_error(kDltImportWhat, "a coefficient is not a finite number");
  if (sensor.width_px < 2 || sensor.height_px < 2)
    throw_calibration_error(kDltImportWhat, "image size not set");
  if (!(sensor.dx_mm > 0 && sensor.dy_mm > 0))
    throw_calibration_error(kDltImportWhat, "the pixel pitch must be positive");
  ProjectionMatrix P;
  P << L[0], L[1], L[2], L[3], L[4], L[5], L[6], L[7], L[8], L[9], L[10], 1.0;
  Eigen::Matrix3d to_rangecal;  // u = x − 0.5, v = H − 0.5 − y
  to_rangecal << 1, 0, -0.5, 0, -1, sensor.height_px - 0.5, 0, 0, 1;
  const KrcDecomposition krc = decompose_projection_matrix(to_rangecal * P);
  const double aspect = krc.K(0, 0) / krc.K(1, 1);
  if (!(aspect >= 0.5 && aspect <= 2))
    throw_calibration_error(kDltImportWhat, "the coefficients' pixels are not square within 2× (fx / fy = " +
                                                std::to_string(aspect) + "): not a camera's DLT");
  // The tools' frame is y-up from the image's bottom edge: coefficients made for another height put
  // the principal point that much elsewhere, off the image when the heights differ enough.
  if (!(krc.K(0, 2) >= 0 && krc.K(0, 2) <= sensor.width_px - 1 && krc.K(1, 2) >= 0 &&
        krc.K(1, 2) <= sensor.height_px - 1))
    throw_calibration_error(kDltImportWhat, "the principal point (" + std::to_string(krc.K(0, 2)) + ", " +
                                                std::to_string(krc.K(1, 2)) + ") px lies off the " +
                                                std::to_string(sensor.width_px) + " × " +
                                                std::to_string(sensor.height_px) +
                                                " image: coefficients for an image of another size?");
  ImportedCamera res;
  res.camera = camera_from_krc(krc, sensor);
  if (skew_px) *skew_px = krc.K(0, 1);

  // What the dropped skew moves: each pixel's DLT ray through rangecal's projection.
  const Eigen::Matrix3d Kinv = krc.K.inverse();
  const CameraIntrinsics& in = res.camera.intr;
  const double intr[4] = {in.f_mm, in.sx, in.u0_px, in.v0_px};
  const std::array<double, 7> d = in.dist.as_array();
  double sum2 = 0, mx = 0;
  int n = 0;
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 64; ++i) {
      const Eigen::Vector3d px((i + 0.37) * (sensor.width_px - 1) / 63.74,
                               (j + 0.37) * (sensor.height_px - 1) / 39.74, 1);
      const Eigen::Vector3d ray = Kinv * px;
      const double xc[3] = {ray.x() / ray.z(), ray.y() / ray.z(), 1.0};
      double u = 0, v = 0;
      double e = std::numeric_limits<double>::infinity();
      if (project_camera_point(intr, d.data(), in.dx_mm, in.dy_mm, xc, &u, &v))
        e = std::hypot(u - px.x(), v - px.y());
      sum2 += e * e;
      mx = std::max(mx, e);
      ++n;
    }
  res.fit_points = n;
  res.fit_max_px = mx;
  res.fit_rms_px = std::sqrt(sum2 / n);
  return res;
}

std::array<double, 11> read_dlt_coefficients_csv(const std::string& path, int column) {
  const std::string text = read_file_text(path);
  if (column < 1) throw_input_error(path, 0, "column", "the camera's column is 1-based (1, 2, …)");
  std::array<double, 11> L{};
  int found = 0;
  long line_no = 0;
  for (std::size_t start = 0; start < text.size();) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + start, end - start);
    start = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line_no == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);
    if (trim(line).empty()) continue;
    if (found == 11)
      throw_input_error(path, line_no, "", "more than 11 coefficient lines: a DLT-11 file has exactly 11");
    const std::vector<std::string> cells = split_trim(line, ',');
    const std::string field = "column " + std::to_string(column);
    if (static_cast<int>(cells.size()) < column)
      throw_input_error(path, line_no, field,
                        "the line has " + std::to_string(cells.size()) + " camera column(s)");
    const std::string& cell = cells[static_cast<std::size_t>(column - 1)];
    const std::optional<double> x = parse_double(cell);
    if (!x)
      throw_input_error(path, line_no, field,
                        "'" + cell + "' is not a finite number (L" + std::to_string(found + 1) + ")");
    L[static_cast<std::size_t>(found++)] = *x;
  }
  if (found != 11)
    throw_input_error(path, 0, "",
                      std::to_string(found) + " coefficient lines; a DLT-11 file has exactly 11 (L1 … L11)");
  return L;
}

}  // namespace rangecal
