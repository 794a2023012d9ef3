#include "vision/calibration/homography.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

#include "config/error.hpp"
#include "vision/calibration/calibration_input_checks.hpp"
#include "vision/calibration/hartley_normalisation.hpp"

namespace rangecal {
Eigen::Matrix3d fit_homography(const std::vector<PointCorrespondence>& pts, const std::string& what) {
  require_finite(pts, what);
  require_min_points(pts, 4, what, "8 unknowns of the homography, 2 equations per point");
  double extent = 0;
  for (const auto& p : pts) extent = std::max(extent, p.world.head<2>().cwiseAbs().maxCoeff());
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (std::abs(pts[i].world.z()) > 1e-9 * std::max(extent, 1e-300))
      throw_calibration_error(
          what, "point " + std::to_string(i) + " is off the target plane: planar targets need world Z = 0");
  const PointGeometry g = classify_world_geometry(pts);
  if (g == PointGeometry::single_point || g == PointGeometry::collinear)
    require_world_geometry(pts, false, what);

  std::vector<Eigen::Vector2d> X, x;
  for (const auto& p : pts) X.push_back(p.world.head<2>()), x.push_back(p.pixel);
  const Eigen::Matrix3d TX = hartley_normalisation<2>(X), Tx = hartley_normalisation<2>(x);
  const Eigen::Index rows = std::max<Eigen::Index>(2 * pts.size(), 9);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(rows, 9);
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const Eigen::Vector3d M = TX * X[k].homogeneous();
    const Eigen::Vector3d m = Tx * x[k].homogeneous();
    const double u = m.x() / m.z(), v = m.y() / m.z();
    // Seed 001 eq. 13: [Mᵀ 0ᵀ −u·Mᵀ; 0ᵀ Mᵀ −v·Mᵀ]·[h¹; h²; h³] = 0 (hʲ the rows of H).
    A.block<1, 3>(2 * k, 0) = M.transpose();
    A.block<1, 3>(2 * k, 6) = -u * M.transpose();
    A.block<1, 3>(2 * k + 1, 3) = M.transpose();
    A.block<1, 3>(2 * k + 1, 6) = -v * M.transpose();
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const auto& s = svd.singularValues();
  if (!s.allFinite() || !(s(0) > 0) || s(7) < 1e-10 * s(0))
    throw_calibration_error(what,
                            "singular system: the homography equations (seed 001 eq. 13) have no unique "
                            "solution (points in degenerate position, e.g. 3 of 4 on a line)");
  const Eigen::VectorXd h = svd.matrixV().col(8);
  Eigen::Matrix3d Hn;
  Hn << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  Eigen::Matrix3d H = Tx.inverse() * Hn * TX;
  H /= H.norm();
  if (H(2, 2) < 0) H = -H;
  return H;
}

}  // namespace rangecal
