#include "pipeline/report/calibration_difference.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "config/error.hpp"
#include "config/number_format.hpp"
#include "pipeline/report/projection_uncertainty.hpp"

namespace rangecal {

CalibrationDifference compare_calibrations(const CalibrationResult& a, const CalibrationResult& b,
                                           double depth_m, int nx, int ny, const std::string& file_b) {
  const CameraIntrinsics &ia = a.camera.intr, &ib = b.camera.intr;
  if (ia.width_px != ib.width_px || ia.height_px != ib.height_px)
    throw_input_error(file_b, 0, "image_size_px",
                      "the calibrations are of different image sizes (" + std::to_string(ia.width_px) + "x" +
                          std::to_string(ia.height_px) + " and " + std::to_string(ib.width_px) + "x" +
                          std::to_string(ib.height_px) + " px): not the same camera");
  CalibrationDifference d;
  d.depth_m = depth_m;
  d.nx = nx;
  d.ny = ny;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double ss = 0;
  int n_exceed = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      DifferenceCell c;
      c.uv_px = Eigen::Vector2d(-0.5 + (i + 0.5) * ia.width_px / nx, -0.5 + (j + 0.5) * ia.height_px / ny);
      const Eigen::Vector3d X = point_on_pixel_ray(a.camera, c.uv_px, depth_m);
      Eigen::Vector2d qa, qb;
      // Both through the same projection, so identical calibrations differ by exactly zero.
      if (!project(a.camera, X, &qa) || !project(b.camera, X, &qb)) {
        c.diff_px = Eigen::Vector2d::Constant(nan);
        c.sigma_px = nan;
        c.mahalanobis = nan;
        d.cells.push_back(c);
        continue;
      }
      c.diff_px = qb - qa;
      const Eigen::Matrix2d S = projection_covariance_px2(a, X) + projection_covariance_px2(b, X);
      const double lmax =
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(S, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
      c.sigma_px = std::sqrt(std::max(0.0, lmax));
      if (c.diff_px.isZero(0)) {
        c.mahalanobis = 0;
      } else if (!(lmax > 0)) {
        c.mahalanobis = std::numeric_limits<double>::infinity();
      } else {
        c.mahalanobis = std::sqrt(std::max(0.0, c.diff_px.dot(S.ldlt().solve(c.diff_px))));
      }
      c.exceeds = c.mahalanobis > kDifferenceExceeds;
      n_exceed += c.exceeds;
      d.max_diff_px = std::max(d.max_diff_px, c.diff_px.norm());
      ss += c.diff_px.squaredNorm();
      d.cells.push_back(c);
    }
  if (!d.cells.empty()) {
    d.rms_diff_px = std::sqrt(ss / static_cast<double>(d.cells.size()));
    d.fraction_exceeding = static_cast<double>(n_exceed) / static_cast<double>(d.cells.size());
  }
  return d;
}

double site_origin_depth_m(const Camera& cam) {
  const double z = world_to_camera(cam.pose, Eigen::Vector3d::Zero()).z();
  return z > 0 ? z : std::numeric_limits<double>::quiet_NaN();
}

std::string format_difference_table(const CalibrationDifference& d) {
  std::string s = "|q_B - q_A| (px) at depth " + format_number("%.2f", d.depth_m) +
                  " m; '*': exceeds the combined sigma (Mahalanobis > " +
                  format_number("%.3f", kDifferenceExceeds) + ", 5 % expected from noise alone)\n";
  s += "   v \\ u";
  for (int i = 0; i < d.nx; ++i) s += format_number("%9.0f", d.cells[static_cast<std::size_t>(i)].uv_px.x());
  s += "\n";
  for (int j = 0; j < d.ny; ++j) {
    s += format_number("%8.0f", d.cells[static_cast<std::size_t>(j * d.nx)].uv_px.y());
    for (int i = 0; i < d.nx; ++i) {
      const DifferenceCell& c = d.cells[static_cast<std::size_t>(j * d.nx + i)];
      s += std::isfinite(c.diff_px.x()) ? format_number("%8.3f", c.diff_px.norm()) + (c.exceeds ? "*" : " ")
                                        : std::string("       - ");
    }
    s += "\n";
  }
  s += "max " + format_number("%.4f", d.max_diff_px) + " px, RMS " + format_number("%.4f", d.rms_diff_px) +
       " px, " + format_number("%.1f", 100 * d.fraction_exceeding) +
       " % of cells exceed the combined sigma\n";
  return s;
}

}  // namespace rangecal
