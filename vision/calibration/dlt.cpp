#include "vision/calibration/dlt.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "config/deterministic_random.hpp"
#include "config/error.hpp"
#include "vision/calibration/calibration_input_checks.hpp"
#include "vision/calibration/hartley_normalisation.hpp"
#include "vision/calibration/rq_decomposition.hpp"

namespace rangecal {
namespace {

const char* const kMethod = "dlt";

// Normalised DLT on the subset `idx`. Returns false when the system's null space is not 1-D.
bool solve_dlt(const std::vector<PointCorrespondence>& pts, const std::vector<std::size_t>& idx,
               ProjectionMatrix* P, double* condition = nullptr) {
  std::vector<Eigen::Vector3d> X;
  std::vector<Eigen::Vector2d> x;
  X.reserve(idx.size());
  x.reserve(idx.size());
  for (std::size_t i : idx) X.push_back(pts[i].world), x.push_back(pts[i].pixel);
  const Eigen::Matrix4d TX = hartley_normalisation<3>(X);
  const Eigen::Matrix3d Tx = hartley_normalisation<2>(x);
  // Seed 000 eq. 2: G·M' = 0, two rows per point; at least 12 rows so the SVD has 12 singular values.
  const Eigen::Index rows = std::max<Eigen::Index>(2 * idx.size(), 12);
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(rows, 12);
  for (std::size_t k = 0; k < idx.size(); ++k) {
    const Eigen::Vector4d Xn = TX * X[k].homogeneous();
    const Eigen::Vector3d xn = Tx * x[k].homogeneous();
    const double u = xn.x() / xn.z(), v = xn.y() / xn.z();
    G.block<1, 4>(2 * k, 0) = Xn.transpose();
    G.block<1, 4>(2 * k, 8) = -u * Xn.transpose();
    G.block<1, 4>(2 * k + 1, 4) = Xn.transpose();
    G.block<1, 4>(2 * k + 1, 8) = -v * Xn.transpose();
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(G, Eigen::ComputeFullV);
  const auto& s = svd.singularValues();
  if (!s.allFinite() || !(s(0) > 0)) return false;
  if (condition) *condition = s(10) / s(0);
  // A second (near-)null direction means the points do not determine P.
  if (s(10) < 1e-10 * s(0)) return false;
  const Eigen::VectorXd m = svd.matrixV().col(11);
  ProjectionMatrix Pn;
  Pn.row(0) = m.segment<4>(0).transpose();
  Pn.row(1) = m.segment<4>(4).transpose();
  Pn.row(2) = m.segment<4>(8).transpose();
  ProjectionMatrix Pd = Tx.inverse() * Pn * TX;  // denormalise
  if (Pd.leftCols<3>().determinant() < 0) Pd = -Pd;
  *P = Pd / Pd.norm();
  return true;
}

// Reprojection distance of point i under P (det(P₃ₓ₃) > 0), +inf when it lies behind the camera.
double reprojection_px(const ProjectionMatrix& P, const PointCorrespondence& pc) {
  const Eigen::Vector3d h = P * pc.world.homogeneous();
  if (!(h.z() > 0)) return std::numeric_limits<double>::infinity();
  return (h.head<2>() / h.z() - pc.pixel).norm();
}

std::vector<std::size_t> inliers_of(const ProjectionMatrix& P, const std::vector<PointCorrespondence>& pts,
                                    double thr) {
  std::vector<std::size_t> in;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (reprojection_px(P, pts[i]) < thr) in.push_back(i);
  return in;
}

}  // namespace

ProjectionMatrix dlt_projection_matrix(const std::vector<PointCorrespondence>& pts) {
  require_finite(pts, kMethod);
  require_min_points(pts, 6, kMethod, "11 unknowns of P, 2 equations per point");
  require_world_geometry(pts, /*need_non_coplanar=*/true, kMethod);
  std::vector<std::size_t> all(pts.size());
  std::iota(all.begin(), all.end(), 0);
  ProjectionMatrix P;
  double cond = 0;
  if (!solve_dlt(pts, all, &P, &cond))
    throw_calibration_error(kMethod,
                            "singular system: the DLT equations (seed 000 eq. 2) have no unique "
                            "solution (relative 11th singular value " +
                                std::to_string(cond) + ")");
  return P;
}

KrcDecomposition decompose_projection_matrix(const ProjectionMatrix& Pin) {
  ProjectionMatrix P = Pin;
  Eigen::Matrix3d M = P.leftCols<3>();
  const double det = M.determinant();
  if (!std::isfinite(det) || std::abs(det) < 1e-14 * std::pow(M.norm(), 3))
    throw_calibration_error(kMethod, "singular projection matrix: its left 3×3 block has rank < 3");
  if (det < 0) P = -P, M = -M;
  const RqResult rq = rq_decompose(M);
  KrcDecomposition out;
  out.K = rq.K / rq.K(2, 2);
  out.R = rq.R;
  out.C = -M.lu().solve(P.col(3));  // P·[C; 1] = 0
  return out;
}

Camera camera_from_krc(const KrcDecomposition& krc, const SensorGeometry& sensor) {
  Camera cam;
  cam.intr.width_px = sensor.width_px;
  cam.intr.height_px = sensor.height_px;
  cam.intr.dx_mm = sensor.dx_mm;
  cam.intr.dy_mm = sensor.dy_mm;
  // u = u0 + sx·f/dx·Xc/Zc, v = v0 + f/dy·Yc/Zc (docs/conventions.md)  ⇒  fx = sx·f/dx, fy = f/dy.
  cam.intr.f_mm = krc.K(1, 1) * sensor.dy_mm;
  cam.intr.sx = krc.K(0, 0) * sensor.dx_mm / cam.intr.f_mm;
  cam.intr.u0_px = krc.K(0, 2);
  cam.intr.v0_px = krc.K(1, 2);
  cam.pose.R = krc.R;
  cam.pose.T = -krc.R * krc.C;
  return cam;
}

namespace {

// RANSAC over 6-point samples (seed 000 eq. 2 on each): the largest consensus set; sets *iterations.
std::vector<std::size_t> ransac_consensus(const std::vector<PointCorrespondence>& pts, const DltOptions& opt,
                                          int* iterations) {
  const std::size_t n = pts.size();
  SampleRandom rng(opt.seed);
  std::vector<std::size_t> best;
  std::vector<std::size_t> sample(6);
  long needed = opt.max_iterations;
  int it = 0, solved = 0;
  for (; it < std::min<long>(needed, opt.max_iterations); ++it) {
    // 6 distinct indices (partial Fisher–Yates over a virtual index list).
    for (int k = 0; k < 6; ++k) {
      std::size_t c;
      do c = rng.below(n);
      while (std::find(sample.begin(), sample.begin() + k, c) != sample.begin() + k);
      sample[k] = c;
    }
    std::vector<PointCorrespondence> sp;
    for (std::size_t i : sample) sp.push_back(pts[i]);
    if (classify_world_geometry(sp, 1e-6) != PointGeometry::general) continue;  // degenerate sample
    ProjectionMatrix P;
    if (!solve_dlt(pts, sample, &P)) continue;
    ++solved;
    auto in = inliers_of(P, pts, opt.inlier_threshold_px);
    if (in.size() > best.size()) {
      best = std::move(in);
      const double w = double(best.size()) / n;
      const double miss = 1.0 - std::pow(w, 6);
      needed = miss <= 1e-12 ? it + 1
                             : static_cast<long>(std::ceil(std::log(1 - opt.confidence) / std::log(miss)));
    }
  }
  *iterations = it;
  if (solved == 0)
    throw_calibration_error(kMethod,
                            "singular system: no 6-point sample gave a unique DLT solution (seed 000 "
                            "eq. 2) in " +
                                std::to_string(it) + " samples");
  if (best.size() < 6)
    throw_calibration_error(kMethod, "RANSAC found no consistent camera: best sample had " +
                                         std::to_string(best.size()) + " inliers within " +
                                         std::to_string(opt.inlier_threshold_px) + " px (need ≥ 6)");
  return best;
}

// Refit on the inliers and re-classify until the set is stable (at most 5 rounds).
std::vector<std::size_t> stable_inliers(const std::vector<PointCorrespondence>& pts,
                                        std::vector<std::size_t> inl, double threshold_px) {
  for (int round = 0; round < 5; ++round) {
    std::vector<PointCorrespondence> ip;
    for (std::size_t i : inl) ip.push_back(pts[i]);
    require_world_geometry(ip, true, kMethod);
    ProjectionMatrix P;
    if (!solve_dlt(pts, inl, &P)) throw_calibration_error(kMethod, "singular system on the RANSAC inliers");
    auto in2 = inliers_of(P, pts, threshold_px);
    if (in2.size() < 6) break;
    if (in2 == inl) break;
    inl = std::move(in2);
  }
  return inl;
}

}  // namespace

DltResult dlt_calibrate(const std::vector<PointCorrespondence>& pts, const SensorGeometry& sensor,
                        const DltOptions& opt) {
  if (!(sensor.dx_mm > 0) || !(sensor.dy_mm > 0) || !std::isfinite(sensor.dx_mm) ||
      !std::isfinite(sensor.dy_mm))
    throw_calibration_error(kMethod, "pixel pitch dx, dy must be finite and > 0 mm");
  require_finite(pts, kMethod);
  require_min_points(pts, 6, kMethod, "11 unknowns of P, 2 equations per point");
  require_world_geometry(pts, /*need_non_coplanar=*/true, kMethod);
  const std::size_t n = pts.size();
  DltResult res;
  std::vector<std::size_t> inl(n);
  std::iota(inl.begin(), inl.end(), 0);

  if (opt.ransac && n > 6) {
    if (!(opt.inlier_threshold_px > 0))
      throw_calibration_error(kMethod, "RANSAC inlier threshold must be > 0 px");
    inl = stable_inliers(pts, ransac_consensus(pts, opt, &res.ransac_iterations), opt.inlier_threshold_px);
  }
  if (!solve_dlt(pts, inl, &res.P))
    throw_calibration_error(kMethod,
                            "singular system: the DLT equations (seed 000 eq. 2) have no unique solution");
  res.inliers = inl;
  for (std::size_t i = 0, k = 0; i < n; ++i) {
    if (k < inl.size() && inl[k] == i)
      ++k;
    else
      res.outliers.push_back(i);
  }
  double ss = 0;
  for (std::size_t i : inl) {
    const double e = reprojection_px(res.P, pts[i]);
    if (!std::isfinite(e))
      throw_calibration_error(kMethod,
                              "point " + std::to_string(i) +
                                  " lies behind the camera of the DLT solution (mirrored or inconsistent "
                                  "correspondences)");
    ss += e * e;
  }
  res.rms_px = std::sqrt(ss / inl.size());
  res.krc = decompose_projection_matrix(res.P);
  res.skew_px = res.krc.K(0, 1);
  res.camera = camera_from_krc(res.krc, sensor);
  ss = 0;
  for (std::size_t i : inl) {
    Eigen::Vector2d uv;
    if (!project(res.camera, pts[i].world, &uv))
      throw_calibration_error(kMethod, "point " + std::to_string(i) + " lies behind the decomposed camera");
    ss += (uv - pts[i].pixel).squaredNorm();
  }
  res.camera_rms_px = std::sqrt(ss / inl.size());
  return res;
}

}  // namespace rangecal
