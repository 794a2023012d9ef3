#include "vision/calibration/tsai.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <ceres/tiny_solver.h>

#include "config/error.hpp"
#include "vision/calibration/calibration_input_checks.hpp"
#include "vision/calibration/nearest_rotation.hpp"

namespace rangecal {
namespace {

const char* const kTsaiMethod = "tsai";

struct SensorPoint {
  double xdp;  // Xd' = (u − u0)·dx = sx·xd (mm)
  double yd;   // (v − v0)·dy (mm)
};

void resolve_principal_point(const TsaiSensor& s, double* u0, double* v0) {
  if (!(s.dx_mm > 0) || !(s.dy_mm > 0) || !std::isfinite(s.dx_mm) || !std::isfinite(s.dy_mm))
    throw_calibration_error(kTsaiMethod, "pixel pitch dx, dy must be finite and > 0 mm");
  *u0 = std::isnan(s.u0_px) ? 0.5 * (s.width_px - 1) : s.u0_px;
  *v0 = std::isnan(s.v0_px) ? 0.5 * (s.height_px - 1) : s.v0_px;
  if (!std::isfinite(*u0) || !std::isfinite(*v0) || (std::isnan(s.u0_px) && s.width_px <= 0) ||
      (std::isnan(s.v0_px) && s.height_px <= 0))
    throw_calibration_error(kTsaiMethod, "principal point unknown: give (u0, v0) or the image size");
}

std::vector<SensorPoint> to_sensor(const std::vector<PointCorrespondence>& pts, const TsaiSensor& s,
                                   double u0, double v0) {
  std::vector<SensorPoint> out(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i)
    out[i] = {(pts[i].pixel.x() - u0) * s.dx_mm, (pts[i].pixel.y() - v0) * s.dy_mm};
  return out;
}

// Least squares with column equilibration and a rank test; throws on a singular system.
Eigen::VectorXd solve_least_squares(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                    const std::string& what) {
  Eigen::VectorXd scale(A.cols());
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    const double n = A.col(j).norm();
    scale(j) = n > 0 ? 1.0 / n : 1.0;
  }
  const Eigen::MatrixXd As = A * scale.asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(As, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const auto& sv = svd.singularValues();
  if (!(sv(0) > 0) || sv(sv.size() - 1) < 1e-11 * sv(0) || !sv.allFinite())
    throw_calibration_error(kTsaiMethod, "singular system in " + what + " (condition number " +
                                             std::to_string(sv(0) / std::max(sv(sv.size() - 1), 1e-300)) +
                                             "): the points do not determine the unknowns");
  return scale.asDiagonal() * svd.solve(b);
}

// Willson's orthonormalisation through roll-pitch-yaw angles (R = Rz·Ry·Rx; SOURCE.md of the
// Tsai sample data gives the element formulas).
Eigen::Matrix3d rpy_rotation(const Eigen::Vector3d& row1, const Eigen::Vector3d& row2) {
  const double r1 = row1(0), r2 = row1(1), r3 = row1(2), r4 = row2(0), r5 = row2(1), r6 = row2(2);
  const double r7 = r2 * r6 - r3 * r5;  // (row1 × row2)_x
  const double rz = std::atan2(r4, r1);
  const double sg = std::sin(rz), cg = std::cos(rz);
  const double ry = std::atan2(-r7, r1 * cg + r4 * sg);
  const double rx = std::atan2(r3 * sg - r6 * cg, r5 * cg - r2 * sg);
  return (Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// How strongly Ty is determined, without dividing by it: the radial alignment constraint (Tsai 1987
// eq. 11) multiplied out is homogeneous,
//   Xd'·(r4 X + r5 Y + r6 Z + Ty) − Yd·(sx r1 X + sx r2 Y + sx r3 Z + sx Tx) = 0,
// in v = (sx r1, sx r2, sx r3, sx Tx, r4, r5, r6, Ty) up to scale; v is the right singular vector of
// the smallest singular value (columns equilibrated), solved with the world coordinates taken about
// the centroid c of the points (centred, so that a world origin kilometres away costs no digits).
// Then yc_i ∝ v5..7·(Xw_i − c) + v8, and in the user's frame Ty ∝ v8 − v5..7·c:
//   ratio = |Ty| / max_i |yc_i|,
// which is 0 when the world origin lies on the camera's XZ plane — where eq. 12, divided by Ty, has
// no solution — and O(1) when the origin is as far off that plane as the farthest point.
struct TyStrength {
  double ratio = 1;         ///< |Ty| / max_i |yc_i| (1 when undeterminable: the eq. 12 solve then reports)
  std::size_t largest = 0;  ///< index of the point with the largest |yc_i|
};

TyStrength ty_strength(const std::vector<PointCorrespondence>& pts, const std::vector<SensorPoint>& sp,
                       const Eigen::Vector3d& c) {
  const std::size_t n = pts.size();
  Eigen::MatrixXd M(n, 8);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d X = pts[i].world - c;
    const double xd = sp[i].xdp, yd = sp[i].yd;
    M.row(i) << -X.x() * yd, -X.y() * yd, -X.z() * yd, -yd, X.x() * xd, X.y() * xd, X.z() * xd, xd;
  }
  Eigen::VectorXd scale(8);
  for (Eigen::Index j = 0; j < 8; ++j) {
    const double col = M.col(j).norm();
    scale(j) = col > 0 ? 1.0 / col : 1.0;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(M * scale.asDiagonal(), Eigen::ComputeFullV);
  const Eigen::VectorXd v = scale.asDiagonal() * svd.matrixV().col(7);
  TyStrength out;
  double largest = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double yc = std::abs(v.segment<3>(4).dot(pts[i].world - c) + v(7));
    if (yc > largest) largest = yc, out.largest = i;
  }
  if (largest > 0 && v.allFinite()) out.ratio = std::abs(v(7) - v.segment<3>(4).dot(c)) / largest;
  return out;
}

using Vector8d = Eigen::Matrix<double, 8, 1>;

// Seed 002 eq. 12 (Tsai 1987 eq. 16 with sx), one row per point, with the world coordinates taken
// about `origin` (Xw' = Xw − origin). Returns v = (L, 1) = (sx r1, sx r2, sx r3, sx Tx', r4, r5, r6, Ty')/Ty'
// with Tx', Ty' those of that frame.
Vector8d solve_eq12(const std::vector<PointCorrespondence>& pts, const std::vector<SensorPoint>& sp,
                    const Eigen::Vector3d& origin, double* rms_mm) {
  const std::size_t n = pts.size();
  Eigen::MatrixXd A(n, 7);
  Eigen::VectorXd b(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d X = pts[i].world - origin;
    const double xd = sp[i].xdp, yd = sp[i].yd;
    A.row(i) << X.x() * yd, X.y() * yd, X.z() * yd, yd, -X.x() * xd, -X.y() * xd, -X.z() * xd;
    b(i) = xd;
  }
  const Eigen::VectorXd L = solve_least_squares(A, b, "Tsai step 1 (seed 002 eq. 12)");
  *rms_mm = std::sqrt((A * L - b).squaredNorm() / n);
  Vector8d v;
  v << L, 1.0;
  return v;
}

// Tsai's recovery of R, Tx, Ty, sx (Tsai 1987 eqs. 17–18 and §III.B step ii) from v ∝ (sx r1, sx r2,
// sx r3, sx Tx, r4, r5, r6, Ty) about `origin`, scaled by ‖r4..r6‖ = 1 rather than by Ty (equal to
// Tsai's formulas when v8 = 1). Tx, Ty of that frame.
void recover_pose(const std::vector<PointCorrespondence>& pts, const std::vector<SensorPoint>& sp,
                  const Vector8d& v, const Eigen::Vector3d& origin, TsaiOrthonormalisation orthonormalisation,
                  TsaiStep1* s1) {
  const std::size_t n = pts.size();
  // 1/|Ty| (with v8 = 1) from the unit norm of row 2 of R (Tsai 1987 eq. 17, with sx unknown).
  const double n2 = v.segment<3>(4).norm();
  if (!(n2 > 0) || !std::isfinite(n2))
    throw_calibration_error(kTsaiMethod, "singular system: r4..r6/Ty vanished (Ty cannot be determined)");
  double t = 1.0 / n2;  // the scale of v, signed below

  // Sign: with t > 0, the predicted (sx·xc, yc) of the point farthest from the image centre must
  // point the same way as its observed (Xd', Yd) (Tsai 1987 §III.B step ii).
  std::size_t far = 0;
  double far_r2 = -1;
  for (std::size_t i = 0; i < n; ++i) {
    const double r2 = sp[i].xdp * sp[i].xdp + sp[i].yd * sp[i].yd;
    if (r2 > far_r2) far_r2 = r2, far = i;
  }
  {
    const Eigen::Vector3d X = pts[far].world - origin;
    const double sxc = (v(0) * X.x() + v(1) * X.y() + v(2) * X.z() + v(3)) * t;
    const double yc = (v(4) * X.x() + v(5) * X.y() + v(6) * X.z() + v(7)) * t;
    if (sxc * sp[far].xdp + yc * sp[far].yd < 0) t = -t;
  }

  // sx from the unit norm of row 1 (Tsai 1987 eq. 18); then rows 1–2 of R and Tx.
  s1->sx = v.head<3>().norm() * std::abs(t);
  if (!(s1->sx > 0) || !std::isfinite(s1->sx))
    throw_calibration_error(kTsaiMethod, "singular system: sx·r1..r3/Ty vanished (sx cannot be determined)");
  const Eigen::Vector3d row1 = v.head<3>() * t / s1->sx;
  const Eigen::Vector3d row2 = v.segment<3>(4) * t;
  // Tsai: L4 = sx·Tx/Ty. Willson's program keeps Tx = L4·Ty (no 1/sx), reproduced in its mode.
  s1->Tx = orthonormalisation == TsaiOrthonormalisation::willson_rpy ? v(3) * t : v(3) * t / s1->sx;
  s1->Ty = v(7) * t;
  s1->orthogonality_error = std::abs(row1.dot(row2));
  Eigen::Matrix3d Rraw;
  Rraw.row(0) = row1.transpose();
  Rraw.row(1) = row2.transpose();
  Rraw.row(2) = row1.cross(row2).transpose();
  s1->R = orthonormalisation == TsaiOrthonormalisation::svd ? nearest_rotation(Rraw)  // Frobenius-nearest
                                                            : rpy_rotation(row1, row2);
}

}  // namespace

TsaiStep1 tsai_step1(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                     TsaiOrthonormalisation orthonormalisation) {
  require_finite(pts, kTsaiMethod);
  require_min_points(pts, 7, kTsaiMethod, "7 unknowns in the linear system of seed 002 eq. 12");
  require_world_geometry(pts, /*need_non_coplanar=*/true, kTsaiMethod);
  TsaiStep1 s1;
  resolve_principal_point(sensor, &s1.u0_px, &s1.v0_px);
  const auto sp = to_sensor(pts, sensor, s1.u0_px, s1.v0_px);

  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : pts) centroid += p.world;
  centroid /= static_cast<double>(pts.size());
  const TyStrength strength = ty_strength(pts, sp, centroid);
  s1.ty_ratio = strength.ratio;
  if (orthonormalisation == TsaiOrthonormalisation::willson_rpy) {
    // The reference program's published run: eq. 12 and the recovery in the user's frame.
    const Vector8d v = solve_eq12(pts, sp, Eigen::Vector3d::Zero(), &s1.linear_rms_mm);
    recover_pose(pts, sp, v, Eigen::Vector3d::Zero(), orthonormalisation, &s1);
    return s1;
  }
  // Tsai 1987 §III.B (the remark after eq. 16): the world origin must lie in the field of view and
  // away from the v = v0 line, since eq. 12 is divided by Ty and its recovery (eqs. 17–18) pivots R
  // about that origin. The user's origin may be anywhere — behind the camera, at it (Ty = 0), or
  // kilometres off the optical axis, where a small error in R becomes a large one in Tx, Ty — so the
  // linear step never uses it. Eq. 12 is solved with the world coordinates taken about the point
  // with the largest |yc| (in view, and as far from the v = v0 line as the points allow), its solution
  // is re-expressed about the centroid of the points (in view: a convex combination of points in
  // view), R, Tx, Ty are recovered there and mapped back exactly. Rotating the world axes needs no
  // such care: it is a linear re-parametrisation of L and leaves the least-squares solution as it is.
  // World coordinates about a point a: Xa = Xw − a, and Xc = R·Xw + T = R·Xa + (T + R·a), so
  // Ta = T + R·a; between two such frames Tb = Ta + R·(b − a), and T = Ta − R·a. The camera centre
  // C = −Rᵀ·T = −Rᵀ·Ta + a is simply shifted. v holds (sx·Tx, Ty) in slots 4 and 8 (scaled by 1/Ty
  // of its frame) with R's rows 1–2 in slots 1–3 and 5–7, hence the re-expression below.
  s1.eq12_origin = pts[strength.largest].world;
  Vector8d v = solve_eq12(pts, sp, s1.eq12_origin, &s1.linear_rms_mm);
  s1.pose_origin = centroid;
  const Eigen::Vector3d ab = s1.pose_origin - s1.eq12_origin;
  v(3) += v.head<3>().dot(ab);
  v(7) += v.segment<3>(4).dot(ab);
  recover_pose(pts, sp, v, s1.pose_origin, orthonormalisation, &s1);
  s1.Tx -= s1.R.row(0).dot(s1.pose_origin);
  s1.Ty -= s1.R.row(1).dot(s1.pose_origin);
  return s1;
}

namespace {

// Camera coordinates of the points under step 1 (xc, yc) and R's row 3 (wz = r7 X + r8 Y + r9 Z,
// zc = wz + Tz), with the observed undistorted-free sensor coordinates (xd = Xd'/sx, yd).
struct StepTwoPoint {
  double xc, yc, wz, xd, yd;
};

std::vector<StepTwoPoint> step_two_points(const std::vector<PointCorrespondence>& pts,
                                          const TsaiSensor& sensor, const TsaiStep1& s1) {
  const auto sp = to_sensor(pts, sensor, s1.u0_px, s1.v0_px);
  std::vector<StepTwoPoint> out(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d& X = pts[i].world;
    out[i] = {s1.R.row(0).dot(X) + s1.Tx, s1.R.row(1).dot(X) + s1.Ty, s1.R.row(2).dot(X), sp[i].xdp / s1.sx,
              sp[i].yd};
  }
  return out;
}

// Tsai 1987 eq. 15, yd·(wz + Tz) = f·yc and likewise with xd (2 rows per point), by least squares.
// Returns false (f, Tz untouched) when the system is singular; *rel_sigma_f is the standard error
// of f from the residual, relative to |f|: large on the f–distance ridge of a narrow field.
bool linear_f_tz(const std::vector<StepTwoPoint>& q, double* f, double* Tz, double* rel_sigma_f) {
  const std::size_t n = q.size();
  Eigen::MatrixXd A(2 * n, 2);
  Eigen::VectorXd b(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    A.row(2 * i) << q[i].xc, -q[i].xd;
    b(2 * i) = q[i].wz * q[i].xd;
    A.row(2 * i + 1) << q[i].yc, -q[i].yd;
    b(2 * i + 1) = q[i].wz * q[i].yd;
  }
  Eigen::VectorXd ft;
  try {
    ft = solve_least_squares(A, b, "the linear f, Tz solve (Tsai 1987 eq. 15)");
  } catch (const Error&) {
    return false;
  }
  if (!ft.allFinite()) return false;
  *f = ft(0);
  *Tz = ft(1);
  const double s2 = (A * ft - b).squaredNorm() / std::max<double>(1.0, 2.0 * n - 2.0);
  const Eigen::Matrix2d N = A.transpose() * A;
  *rel_sigma_f = std::sqrt(std::max(0.0, s2 * N(1, 1) / N.determinant())) / std::max(std::abs(*f), 1e-300);
  return true;
}

// The eq. 13 cost without distortion at depth offset Tz, with f either given or (f_fixed ≤ 0) at
// its least-squares value for that Tz (closed form: f = Σ(xd·a + yd·b)/Σ(a² + b²), a = xc/zc,
// b = yc/zc, of either sign). +∞ with a point at zc ≤ 0.
double profile_cost(const std::vector<StepTwoPoint>& q, double Tz, double f_fixed, double* f_out) {
  double sab = 0, saa = 0;
  for (const auto& p : q) {
    const double zc = p.wz + Tz;
    if (!(zc > 0)) return std::numeric_limits<double>::infinity();
    const double a = p.xc / zc, b = p.yc / zc;
    sab += p.xd * a + p.yd * b;
    saa += a * a + b * b;
  }
  const double f = f_fixed > 0 ? f_fixed : (saa > 0 ? sab / saa : 0.0);
  double ss = 0;
  for (const auto& p : q) {
    const double zc = p.wz + Tz;
    ss += std::pow(p.xd - f * p.xc / zc, 2) + std::pow(p.yd - f * p.yc / zc, 2);
  }
  *f_out = f;
  return ss;
}

// Tz minimising profile_cost, searched over the nearest point's depth zmin = min zc from 1e-3 to
// 1e5 × the extent of the points (log grid, then golden section in the best bracket): the whole
// feasible range in front of the camera, so no start is needed. Returns Tz and sets *f.
double profile_tz(const std::vector<StepTwoPoint>& q, double extent, double f_fixed, double* f) {
  double wz_min = std::numeric_limits<double>::infinity();
  for (const auto& p : q) wz_min = std::min(wz_min, p.wz);
  const auto cost = [&](double t, double* fo) { return profile_cost(q, std::exp(t) - wz_min, f_fixed, fo); };
  const int n_grid = 240;
  const double t0 = std::log(1e-3 * extent), t1 = std::log(1e5 * extent), dt = (t1 - t0) / n_grid;
  int best = 0;
  double best_cost = std::numeric_limits<double>::infinity(), fo = 0;
  for (int k = 0; k <= n_grid; ++k) {
    const double c = cost(t0 + k * dt, &fo);
    if (c < best_cost) best_cost = c, best = k;
  }
  double a = t0 + std::max(best - 1, 0) * dt, b = t0 + std::min(best + 1, n_grid) * dt;
  const double g = 0.5 * (std::sqrt(5.0) - 1);
  for (int it = 0; it < 60; ++it) {
    const double c1 = b - g * (b - a), c2 = a + g * (b - a);
    if (cost(c1, &fo) < cost(c2, &fo))
      b = c2;
    else
      a = c1;
  }
  const double t = 0.5 * (a + b);
  cost(t, f);
  return std::exp(t) - wz_min;
}

// Turning the camera 180° about its axis negates rows 1–2 of R, Tx, Ty (and so f) together and
// keeps R proper: the fix when step 1's sign test picked the wrong Ty.
void turn_about_axis(TsaiStep1* s1) {
  s1->R.row(0) *= -1;
  s1->R.row(1) *= -1;
  s1->Tx = -s1->Tx;
  s1->Ty = -s1->Ty;
}

bool all_in_front(const std::vector<StepTwoPoint>& q, double Tz) {
  return std::all_of(q.begin(), q.end(), [&](const StepTwoPoint& p) { return p.wz + Tz > 0; });
}

// Above this relative standard error of the linear f, eq. 15 is on the f–distance ridge of a narrow
// field (tests/unit/optim/tsai_property_test.cpp).
constexpr double kMaxLinearFSigma = 0.1;

}  // namespace

std::pair<double, double> tsai_linear_f_tz(const std::vector<PointCorrespondence>& pts,
                                           const TsaiSensor& sensor, TsaiStep1* s1) {
  const auto q = step_two_points(pts, sensor, *s1);
  double f = 0, Tz = 0, rel = 0;
  if (!linear_f_tz(q, &f, &Tz, &rel))
    throw_calibration_error(kTsaiMethod,
                            "singular system in the linear f, Tz solve (Tsai 1987 eq. 15): the points do not "
                            "determine the unknowns");
  if (f < 0) turn_about_axis(s1), f = -f;
  for (std::size_t i = 0; i < q.size(); ++i)
    if (!(q[i].wz + Tz > 0))
      throw_calibration_error(kTsaiMethod,
                              "point " + std::to_string(i) +
                                  " lies behind the camera in the linear solution (inconsistent or "
                                  "mirrored correspondences)");
  return {f, Tz};
}

TsaiStart tsai_f_tz_start(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                          TsaiStep1* s1, double nominal_f_mm) {
  const auto q = step_two_points(pts, sensor, *s1);
  TsaiStart st;
  double f = 0, Tz = 0;
  if (linear_f_tz(q, &f, &Tz, &st.f_linear_rel_sigma)) {
    st.f_linear_mm = std::abs(f);
    st.Tz_linear = Tz;
    if (st.f_linear_rel_sigma <= kMaxLinearFSigma && all_in_front(q, Tz)) {
      if (f < 0) turn_about_axis(s1);
      st.f_mm = std::abs(f), st.Tz = Tz, st.source = TsaiStartSource::linear;
      return st;
    }
  }
  // The ridge: f and the distance trade along it, and the linear solve (which weights the points by
  // their depth) may leave it on the wrong side of the camera. The depth profile of eq. 13 gives the
  // sign of f (so of Ty) and, with no lens given, the start itself.
  double extent = 0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : pts) c += p.world / static_cast<double>(pts.size());
  for (const auto& p : pts) extent = std::max(extent, (p.world - c).norm());
  st.Tz = profile_tz(q, extent, 0.0, &st.f_mm);
  if (!(std::isfinite(st.f_mm) && st.f_mm != 0))
    throw_calibration_error(kTsaiMethod, "no focal length fits the points in front of the camera (f = " +
                                             std::to_string(st.f_mm) + " mm): inconsistent correspondences");
  if (st.f_mm < 0) turn_about_axis(s1), st.f_mm = -st.f_mm;
  st.source = TsaiStartSource::depth_profile;
  if (nominal_f_mm > 0 && std::isfinite(nominal_f_mm)) {
    // The lens's marking fixes the position along the ridge; Tz is then the best depth for it.
    double f_fixed = 0;
    st.Tz = profile_tz(step_two_points(pts, sensor, *s1), extent, nominal_f_mm, &f_fixed);
    st.f_mm = nominal_f_mm;
    st.source = TsaiStartSource::nominal_focal_length;
  }
  return st;
}

double tsai_eq13_cost(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                      const TsaiStep1& s1, double f_mm, double Tz, double k1, Eigen::VectorXd* residuals) {
  double ss = 0;
  if (residuals) residuals->resize(2 * pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d& X = pts[i].world;
    const double xd = (pts[i].pixel.x() - s1.u0_px) * sensor.dx_mm / s1.sx;
    const double yd = (pts[i].pixel.y() - s1.v0_px) * sensor.dy_mm;
    const double r2 = xd * xd + yd * yd;
    const double zc = s1.R.row(2).dot(X) + Tz;
    // Seed 002 eq. 13.
    const double gx = xd * (1 + k1 * r2) - f_mm * (s1.R.row(0).dot(X) + s1.Tx) / zc;
    const double gy = yd * (1 + k1 * r2) - f_mm * (s1.R.row(1).dot(X) + s1.Ty) / zc;
    if (residuals) (*residuals)(2 * i) = gx, (*residuals)(2 * i + 1) = gy;
    ss += gx * gx + gy * gy;
  }
  return ss;
}

Camera tsai_camera(const TsaiSensor& sensor, const TsaiStep1& s1, double f_mm, double Tz, double k1) {
  Camera cam;
  cam.intr.width_px = sensor.width_px;
  cam.intr.height_px = sensor.height_px;
  cam.intr.dx_mm = sensor.dx_mm;
  cam.intr.dy_mm = sensor.dy_mm;
  cam.intr.f_mm = f_mm;
  cam.intr.sx = s1.sx;
  cam.intr.u0_px = s1.u0_px;
  cam.intr.v0_px = s1.v0_px;
  cam.intr.dist.k1 = k1;
  cam.pose.R = s1.R;
  cam.pose.T = {s1.Tx, s1.Ty, Tz};
  return cam;
}

namespace {

// Seed 002 eq. 13 residuals of step 2 over z = (f, Tz[, k1]) / scale, with their analytic Jacobian,
// for ceres::TinySolver (NP = 2: k1 fixed at 0).
template <int NP>
struct TsaiStep2Residuals {
  using Scalar = double;
  enum { NUM_RESIDUALS = Eigen::Dynamic, NUM_PARAMETERS = NP };
  const std::vector<PointCorrespondence>& pts;
  const TsaiSensor& sensor;
  const TsaiStep1& s1;
  const Eigen::Vector3d& scale;

  int NumResiduals() const { return 2 * static_cast<int>(pts.size()); }
  bool operator()(const double* z, double* r, double* J) const {
    const double f = z[0] * scale(0), Tz = z[1] * scale(1), k1 = NP == 3 ? z[NP - 1] * scale(2) : 0.0;
    const std::size_t m = 2 * pts.size();
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Vector3d& X = pts[i].world;
      const double xd = (pts[i].pixel.x() - s1.u0_px) * sensor.dx_mm / s1.sx;
      const double yd = (pts[i].pixel.y() - s1.v0_px) * sensor.dy_mm;
      const double r2 = xd * xd + yd * yd;
      const double xc = s1.R.row(0).dot(X) + s1.Tx, yc = s1.R.row(1).dot(X) + s1.Ty;
      const double zc = s1.R.row(2).dot(X) + Tz;
      r[2 * i] = xd * (1 + k1 * r2) - f * xc / zc;
      r[2 * i + 1] = yd * (1 + k1 * r2) - f * yc / zc;
      if (J) {  // column-major m × NP
        J[2 * i] = -xc / zc * scale(0);
        J[2 * i + 1] = -yc / zc * scale(0);
        J[m + 2 * i] = f * xc / (zc * zc) * scale(1);
        J[m + 2 * i + 1] = f * yc / (zc * zc) * scale(1);
        if (NP == 3) J[2 * m + 2 * i] = xd * r2 * scale(2), J[2 * m + 2 * i + 1] = yd * r2 * scale(2);
      }
    }
    return true;
  }
};

// ceres::TinySolver's Levenberg–Marquardt on the eq. 13 residuals from *p = (f, Tz, k1); sets
// res->iterations and res->converged (a step below 1e-14 of ‖z‖ or no cost change left: machine
// precision). Returns the final sum of squares.
template <int NP>
double solve_step2(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor, const TsaiStep1& s1,
                   const Eigen::Vector3d& scale, int max_iterations, Eigen::Vector3d* p, TsaiResult* res) {
  using Solver = ceres::TinySolver<TsaiStep2Residuals<NP>>;
  Solver solver;
  solver.options.max_num_iterations = max_iterations;
  solver.options.parameter_tolerance = 1e-14;
  solver.options.function_tolerance = 0;
  solver.options.gradient_tolerance = 0;
  solver.options.cost_threshold = 0;
  typename Solver::Parameters z = (p->head<NP>().array() / scale.head<NP>().array()).matrix();
  const auto& summary = solver.Solve(TsaiStep2Residuals<NP>{pts, sensor, s1, scale}, &z);
  p->head<NP>() = (z.array() * scale.head<NP>().array()).matrix();
  res->iterations = summary.iterations;
  res->converged = summary.status != Solver::HIT_MAX_ITERATIONS;
  return tsai_eq13_cost(pts, sensor, s1, (*p)(0), (*p)(1), (*p)(2), nullptr);
}

}  // namespace

namespace {

// Σ pixel reprojection error² of `cam` over the points; false when a point does not project.
bool projected_sum_of_squares(const std::vector<PointCorrespondence>& pts, const Camera& cam, double* ss) {
  *ss = 0;
  for (const auto& pt : pts) {
    Eigen::Vector2d uv;
    if (!project(cam, pt.world, &uv)) return false;
    *ss += (uv - pt.pixel).squaredNorm();
  }
  return std::isfinite(*ss);
}

}  // namespace

TsaiResult tsai_calibrate(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                          const TsaiOptions& options) {
  return tsai_step2(pts, sensor, tsai_step1(pts, sensor, options.orthonormalisation), options);
}

TsaiResult tsai_step2(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor, TsaiStep1 step1,
                      const TsaiOptions& options) {
  TsaiResult res;
  res.step1 = step1;
  require_finite(pts, kTsaiMethod);
  if (options.estimate_k1)
    require_min_points(pts, 8, kTsaiMethod,
                       "step 1 uses 7 unknowns; f, Tz, k1 need an 8th independent point");
  res.start = tsai_f_tz_start(pts, sensor, &res.step1, options.nominal_f_mm);
  res.f_linear_mm = res.start.f_linear_mm;
  res.Tz_linear = res.start.Tz_linear;
  const std::pair<double, double> ft(res.start.f_mm, res.start.Tz);
  const TsaiStep1& s1 = res.step1;
  const std::size_t n = pts.size();

  // Natural scales: the solver works on z = (f, Tz, k1) / scale, so its step tolerance is relative
  // for f and Tz and relative to 1/r_max² for k1.
  double rmax2 = 0;
  for (const auto& p : pts) {
    const double xd = (p.pixel.x() - s1.u0_px) * sensor.dx_mm / s1.sx,
                 yd = (p.pixel.y() - s1.v0_px) * sensor.dy_mm;
    rmax2 = std::max(rmax2, xd * xd + yd * yd);
  }
  const Eigen::Vector3d scale(ft.first != 0 ? std::abs(ft.first) : 1.0,
                              ft.second != 0 ? std::abs(ft.second) : 1.0, 1.0 / std::max(rmax2, 1e-12));
  Eigen::Vector3d p(ft.first, ft.second, 0.0);
  double cost = options.estimate_k1
                    ? solve_step2<3>(pts, sensor, s1, scale, options.max_iterations, &p, &res)
                    : solve_step2<2>(pts, sensor, s1, scale, options.max_iterations, &p, &res);
  double ss = 0;
  if (!(p(0) > 0) || !p.allFinite() ||
      !projected_sum_of_squares(pts, tsai_camera(sensor, s1, p(0), p(1), p(2)), &ss)) {
    // With few or nearly degenerate points the LM over k1 can leave the region where the model
    // projects every point (a distortion that does not invert over the image, or a point behind
    // the camera): f and Tz alone from the same start, and failing that the start itself (every
    // point in front of it by construction, tsai_f_tz_start).
    res.fallback = "k1 held at 0: with k1 free the solution did not project every point";
    p = Eigen::Vector3d(ft.first, ft.second, 0.0);
    cost = solve_step2<2>(pts, sensor, s1, scale, options.max_iterations, &p, &res);
    if (!(p(0) > 0) || !p.allFinite() ||
        !projected_sum_of_squares(pts, tsai_camera(sensor, s1, p(0), p(1), 0), &ss)) {
      res.fallback = "step 2 kept its start (k1 = 0): the nonlinear solution did not project every point";
      p = Eigen::Vector3d(ft.first, ft.second, 0.0);
      cost = tsai_eq13_cost(pts, sensor, s1, p(0), p(1), 0.0, nullptr);
      res.converged = false;
      if (!projected_sum_of_squares(pts, tsai_camera(sensor, s1, p(0), p(1), 0), &ss))
        throw_calibration_error(kTsaiMethod, "a point does not project with the solved camera (behind it)");
    }
  }
  res.camera = tsai_camera(sensor, s1, p(0), p(1), p(2));
  res.rms_sensor_mm = std::sqrt(cost / (2.0 * n));
  res.rms_px = std::sqrt(ss / n);
  return res;
}

namespace {

// Seed 002 eq. 13 with every parameter free: intr = {f, sx, u0, v0, k1}; w = angle-axis of R; t = T.
struct TsaiFullResidual {
  double X, Y, Z, u, v, dx, dy;
  template <typename T>
  bool operator()(const T* intr, const T* w, const T* t, T* res) const {
    const T p[3] = {T(X), T(Y), T(Z)};
    T xc[3];
    ceres::AngleAxisRotatePoint(w, p, xc);
    for (int k = 0; k < 3; ++k) xc[k] += t[k];
    const T xd = (T(u) - intr[2]) * T(dx) / intr[1];
    const T yd = (T(v) - intr[3]) * T(dy);
    const T c = T(1) + intr[4] * (xd * xd + yd * yd);
    res[0] = xd * c - intr[0] * xc[0] / xc[2];
    res[1] = yd * c - intr[0] * xc[1] / xc[2];
    return true;
  }
};

}  // namespace

TsaiResult tsai_full_refinement(const std::vector<PointCorrespondence>& pts, const Camera& start,
                                int max_iterations) {
  require_finite(pts, kTsaiMethod);
  require_min_points(pts, 11, kTsaiMethod, "11 unknowns in the full refinement");
  require_world_geometry(pts, /*need_non_coplanar=*/true, kTsaiMethod);
  const auto& in = start.intr;
  double intr[5] = {in.f_mm, in.sx, in.u0_px, in.v0_px, in.dist.k1};
  const Eigen::AngleAxisd aa(start.pose.R);
  Eigen::Vector3d w = aa.angle() * aa.axis();
  Eigen::Vector3d t = start.pose.T;
  ceres::Problem problem;
  for (const auto& p : pts)
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<TsaiFullResidual, 2, 5, 3, 3>(new TsaiFullResidual{
            p.world.x(), p.world.y(), p.world.z(), p.pixel.x(), p.pixel.y(), in.dx_mm, in.dy_mm}),
        nullptr, intr, w.data(), t.data());
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = max_iterations;
  so.num_threads = 1;
  so.function_tolerance = 1e-16;
  so.gradient_tolerance = 1e-16;
  so.parameter_tolerance = 1e-14;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (!summary.IsSolutionUsable() || !(intr[0] > 0) || !(intr[1] > 0))
    throw_calibration_error(kTsaiMethod, "full refinement failed: " + summary.message);
  TsaiResult res;
  res.camera = start;
  res.camera.intr.f_mm = intr[0];
  res.camera.intr.sx = intr[1];
  res.camera.intr.u0_px = intr[2];
  res.camera.intr.v0_px = intr[3];
  res.camera.intr.dist = Distortion{};
  res.camera.intr.dist.k1 = intr[4];
  const double a = w.norm();
  res.camera.pose.R = a > 0 ? Eigen::AngleAxisd(a, w / a).toRotationMatrix() : Eigen::Matrix3d::Identity();
  res.camera.pose.T = t;
  res.step1.R = res.camera.pose.R;
  res.step1.Tx = t.x();
  res.step1.Ty = t.y();
  res.step1.sx = intr[1];
  res.step1.u0_px = intr[2];
  res.step1.v0_px = intr[3];
  res.iterations = static_cast<int>(summary.iterations.size()) - 1;
  res.converged = summary.termination_type == ceres::CONVERGENCE;
  res.rms_sensor_mm = std::sqrt(2.0 * summary.final_cost / (2.0 * pts.size()));
  double ss = 0;
  for (const auto& pt : pts) {
    Eigen::Vector2d uv;
    if (!project(res.camera, pt.world, &uv))
      throw_calibration_error(kTsaiMethod, "a point does not project with the refined camera (behind it)");
    ss += (uv - pt.pixel).squaredNorm();
  }
  res.rms_px = std::sqrt(ss / pts.size());
  return res;
}

}  // namespace rangecal
