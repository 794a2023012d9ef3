#include "vision/calibration/calibration_input_checks.hpp"

#include <Eigen/SVD>
#include <cmath>

#include "config/error.hpp"

namespace rangecal {

PointGeometry classify_world_geometry(const std::vector<PointCorrespondence>& pts, double rel_tol) {
  if (pts.empty()) return PointGeometry::single_point;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : pts) mean += p.world;
  mean /= static_cast<double>(pts.size());
  Eigen::MatrixXd A(pts.size(), 3);
  for (std::size_t i = 0; i < pts.size(); ++i) A.row(i) = (pts[i].world - mean).transpose();
  const Eigen::Vector3d s = Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
  const double scale = std::max(s(0), mean.norm() * 1e-12);
  if (!(s(0) > 0) || s(0) <= 1e-12 * std::max(1.0, mean.norm())) return PointGeometry::single_point;
  if (s(1) <= rel_tol * scale) return PointGeometry::collinear;
  if (s(2) <= rel_tol * scale) return PointGeometry::coplanar;
  return PointGeometry::general;
}

void require_finite(const std::vector<PointCorrespondence>& pts, const std::string& method) {
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!pts[i].world.allFinite() || !pts[i].pixel.allFinite())
      throw_calibration_error(method, "point " + std::to_string(i) + " has a NaN or infinite coordinate " +
                                          (pts[i].world.allFinite() ? "(pixel)" : "(world)"));
  }
}

void require_min_points(const std::vector<PointCorrespondence>& pts, std::size_t n, const std::string& method,
                        const std::string& why) {
  if (pts.size() < n)
    throw_calibration_error(method, "too few points: " + std::to_string(pts.size()) + " given, at least " +
                                        std::to_string(n) + " needed (" + why + ")");
}

void require_world_geometry(const std::vector<PointCorrespondence>& pts, bool need_non_coplanar,
                            const std::string& method) {
  switch (classify_world_geometry(pts)) {
    case PointGeometry::single_point:
      throw_calibration_error(method, "degenerate geometry: all world points coincide");
    case PointGeometry::collinear:
      throw_calibration_error(method,
                              "degenerate geometry: all world points lie on one line (e.g. a single vertical "
                              "ascent); add points off that line");
    case PointGeometry::coplanar:
      if (need_non_coplanar)
        throw_calibration_error(method,
                                "degenerate geometry: all world points are coplanar, but this method needs "
                                "non-coplanar points (use the planar method, or add points off the plane)");
      break;
    case PointGeometry::general:
      break;
  }
}

}  // namespace rangecal
