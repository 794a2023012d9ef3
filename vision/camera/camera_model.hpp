#pragma once
// Tsai's camera model as rangecal uses it (docs/conventions.md; seed 002 eqs. 6–7; Tsai 1987), with the
// richer additive distortion terms of seed 000 eq. 7.
//
// Frames and units:
//   world   ENU metres (x east, y north, z up);  Xc = R·Xw + T,  camera centre C = −Rᵀ·T.
//   camera  x right, y down, z along the optical axis (metres).
//   sensor  millimetres on the image plane, about the principal point, x right, y down.
//   pixels  (u, v), u right, v down, centre of the top-left pixel is (0, 0).
//
// Projection (world → pixel):
//   xu = f·Xc/Zc,  yu = f·Yc/Zc                        (undistorted sensor mm; seed 002 eq. 6)
//   (xu, yu) = (xd, yd) + Δ(xd, yd)                    (distortion maps distorted → undistorted)
//   Δx = xd·(k1 r² + k2 r⁴ + k3 r⁶) + p1 (r² + 2 xd²) + 2 p2 xd yd
//   Δy = yd·(k1 r² + k2 r⁴ + k3 r⁶) + p2 (r² + 2 yd²) + 2 p1 xd yd + a1 xd + a2 yd
//                                                      (seed 000 eq. 7; r² = xd² + yd², mm²)
//   u = u0 + sx·xd/dx,  v = v0 + yd/dy                 (dx, dy pixel pitch in mm)
// With only k1 this is exactly seed 002 eq. 7 / Tsai's model. `project` inverts the distortion
// by Newton's method to < 1e-6 px; the templated form works with Ceres Jets (autodiff).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <string>
#include <type_traits>

namespace rangecal {

/// Distortion coefficients, distorted → undistorted, sensor mm (k1 in mm⁻², k2 mm⁻⁴, k3 mm⁻⁶,
/// p1 p2 in mm⁻¹, a1 a2 dimensionless). Array order is kDistortionParameters's
/// (vision/camera/camera_parameters.hpp).
struct Distortion {
  double k1 = 0, k2 = 0, k3 = 0, p1 = 0, p2 = 0, a1 = 0, a2 = 0;
  std::array<double, 7> as_array() const { return {k1, k2, k3, p1, p2, a1, a2}; }
  static Distortion from_array(const double* a) { return {a[0], a[1], a[2], a[3], a[4], a[5], a[6]}; }
};

/// Intrinsic parameters. f in mm, principal point in px, pixel pitch in mm.
struct CameraIntrinsics {
  int width_px = 0;
  int height_px = 0;
  double dx_mm = 0;  ///< horizontal pixel pitch (mm)
  double dy_mm = 0;  ///< vertical pixel pitch (mm)
  double f_mm = 0;   ///< effective focal length (mm)
  double sx = 1;     ///< horizontal scale factor (Tsai's sx)
  double u0_px = 0;  ///< principal point (px)
  double v0_px = 0;
  Distortion dist;
};

/// Exterior orientation: R rotates world (ENU) into camera axes; Xc = R·Xw + T (metres).
struct CameraPose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d T = Eigen::Vector3d::Zero();
  /// Camera centre in world coordinates: C = −Rᵀ·T.
  Eigen::Vector3d center() const { return -R.transpose() * T; }
};

struct Camera {
  std::string id;
  CameraIntrinsics intr;
  CameraPose pose;
};

// ---------------------------------------------------------------------------------------------
// Templated building blocks (usable with double and ceres::Jet). `d` points to 7 coefficients
// in Distortion::as_array() order.

/// Δ of seed 000 eq. 7 at distorted sensor point (xd, yd).
template <typename T>
inline void distortion_delta(const T* d, const T& xd, const T& yd, T* dx, T* dy) {
  const T r2 = xd * xd + yd * yd;
  const T radial = d[0] * r2 + d[1] * r2 * r2 + d[2] * r2 * r2 * r2;
  *dx = xd * radial + d[3] * (r2 + T(2) * xd * xd) + T(2) * d[4] * xd * yd;
  *dy = yd * radial + d[4] * (r2 + T(2) * yd * yd) + T(2) * d[3] * xd * yd + d[5] * xd + d[6] * yd;
}

/// Distorted → undistorted sensor mm (closed form).
template <typename T>
inline void undistort_sensor(const T* d, const T& xd, const T& yd, T* xu, T* yu) {
  T ddx, ddy;
  distortion_delta(d, xd, yd, &ddx, &ddy);
  *xu = xd + ddx;
  *yu = yd + ddy;
}

/// J_F = ∂(xd + Δ(xd))/∂xd, the Jacobian of the distorted → undistorted map at the distorted
/// sensor point (x, y) (seed 000 eq. 7 differentiated), row-major in j = {j11, j12, j21, j22}.
template <typename T>
inline void distortion_jacobian(const T* d, const T& x, const T& y, T* j) {
  const T r2 = x * x + y * y;
  const T radial = d[0] * r2 + d[1] * r2 * r2 + d[2] * r2 * r2 * r2;
  const T dradial_dr2 = d[0] + T(2) * d[1] * r2 + T(3) * d[2] * r2 * r2;
  j[0] = T(1) + radial + T(2) * x * x * dradial_dr2 + T(6) * d[3] * x + T(2) * d[4] * y;
  j[1] = T(2) * x * y * dradial_dr2 + T(2) * d[3] * y + T(2) * d[4] * x;
  j[2] = T(2) * x * y * dradial_dr2 + T(2) * d[4] * x + T(2) * d[3] * y + d[5];
  j[3] = T(1) + radial + T(2) * y * y * dradial_dr2 + T(6) * d[4] * y + T(2) * d[3] * x + d[6];
}

/// The Newton step J_F⁻¹·F of F(xd) = xd + Δ(xd) − xu at (x, y), F in the scalar type T with the
/// coefficients `d`, and J_F in the scalar type S at (xj, yj) with the coefficients `dj` (the same
/// point and coefficients, or their values alone; see distort_sensor).
template <typename T, typename S>
inline void distortion_newton_step(const T* d, const S* dj, const T& x, const T& y, const S& xj, const S& yj,
                                   const T& xu, const T& yu, T* sx, T* sy) {
  T ddx, ddy;
  distortion_delta(d, x, y, &ddx, &ddy);
  const T fx = x + ddx - xu, fy = y + ddy - yu;
  S j[4];
  distortion_jacobian(dj, xj, yj, j);
  const S det = j[0] * j[3] - j[1] * j[2];
  *sx = (j[3] * fx - j[1] * fy) / det;
  *sy = (j[0] * fy - j[2] * fx) / det;
}

/// Undistorted → distorted sensor mm by Newton's method on F(xd) = xd + Δ(xd) − xu, in the
/// scalar type T throughout (see distort_sensor).
template <typename T>
inline bool distort_sensor_newton(const T* d, const T& xu, const T& yu, T* xd, T* yd) {
  using std::abs;
  T x = xu, y = yu;
  for (int it = 0; it < 30; ++it) {
    T sx, sy;
    distortion_newton_step(d, d, x, y, x, y, xu, yu, &sx, &sy);
    x -= sx;
    y -= sy;
    if (abs(sx) + abs(sy) < T(1e-13)) {
      *xd = x;
      *yd = y;
      return true;
    }
  }
  *xd = x;
  *yd = y;
  return false;
}

/// The value part of a scalar: itself for a double, the real part of a ceres::Jet.
template <typename T>
inline double scalar_value(const T& x) {
  if constexpr (std::is_arithmetic_v<T>)
    return static_cast<double>(x);
  else
    return x.a;
}

/// Undistorted → distorted sensor mm. Converges to machine precision for any physically sensible
/// lens (|Δ| ≪ r). Returns false if it did not converge (e.g. a point beyond the fold of a
/// strongly barrel-distorted model).
/// For autodiff types (Jets) the Newton iterations run on the values alone and a single Newton
/// step in T is taken from the converged point: there F = 0, so that step's derivative is
/// −J⁻¹·∂F, exactly the implicit-function theorem's dxd — the same first derivatives as
/// iterating in Jets, at a fraction of the cost (the bundle's hot path).
template <typename T>
inline bool distort_sensor(const T* d, const T& xu, const T& yu, T* xd, T* yd) {
  if constexpr (std::is_arithmetic_v<T>) {
    return distort_sensor_newton(d, xu, yu, xd, yd);
  } else {
    double dv[7];
    for (int k = 0; k < 7; ++k) dv[k] = scalar_value(d[k]);
    double x0 = 0, y0 = 0;
    const bool ok = distort_sensor_newton(dv, scalar_value(xu), scalar_value(yu), &x0, &y0);
    const T x(x0), y(y0);
    // J_F at the converged point, values only (its derivative multiplies F = 0).
    T sx, sy;
    distortion_newton_step(d, dv, x, y, x0, y0, xu, yu, &sx, &sy);
    *xd = x - sx;
    *yd = y - sy;
    return ok;
  }
}

/// Distorted sensor mm → pixel: u = u0 + sx·xd/dx, v = v0 + yd/dy.
template <typename T>
inline void sensor_to_pixel(const T& sx, const T& u0, const T& v0, double dx_mm, double dy_mm, const T& xd,
                            const T& yd, T* u, T* v) {
  *u = u0 + sx * xd / T(dx_mm);
  *v = v0 + yd / T(dy_mm);
}

/// Pixel → distorted sensor mm (inverse of sensor_to_pixel).
template <typename T>
inline void pixel_to_sensor(const T& sx, const T& u0, const T& v0, double dx_mm, double dy_mm, const T& u,
                            const T& v, T* xd, T* yd) {
  *xd = (u - u0) * T(dx_mm) / sx;
  *yd = (v - v0) * T(dy_mm);
}

/// Camera-frame point (metres) → pixel, for autodiff. intr = {f_mm, sx, u0, v0}; d = 7 distortion
/// coefficients. Returns false behind the camera or if the distortion inverse failed.
template <typename T>
inline bool project_camera_point(const T* intr, const T* d, double dx_mm, double dy_mm, const T* xc, T* u,
                                 T* v) {
  if (!(xc[2] > T(0))) return false;
  const T xu = intr[0] * xc[0] / xc[2];
  const T yu = intr[0] * xc[1] / xc[2];
  T xd, yd;
  const bool ok = distort_sensor(d, xu, yu, &xd, &yd);
  sensor_to_pixel(intr[1], intr[2], intr[3], dx_mm, dy_mm, xd, yd, u, v);
  return ok;
}

// ---------------------------------------------------------------------------------------------
// Double-precision conveniences.

/// World ENU (m) → camera frame (m).
inline Eigen::Vector3d world_to_camera(const CameraPose& pose, const Eigen::Vector3d& Xw) {
  return pose.R * Xw + pose.T;
}

/// World ENU (m) → pixel. Returns false when the point is behind the camera or the distortion
/// inverse fails; `uv` is then unspecified.
bool project(const Camera& cam, const Eigen::Vector3d& Xw, Eigen::Vector2d* uv);

/// Whether pixel (u, v) lies on the image: 0 ≤ u ≤ W − 1 and 0 ≤ v ≤ H − 1 (pixel centres,
/// docs/conventions.md).
inline bool inside_image(const CameraIntrinsics& in, const Eigen::Vector2d& uv) {
  return uv.x() >= 0 && uv.y() >= 0 && uv.x() <= in.width_px - 1 && uv.y() <= in.height_px - 1;
}

/// Pixel → unit ray direction in world ENU (undistorts exactly, closed form).
Eigen::Vector3d pixel_ray_world(const Camera& cam, const Eigen::Vector2d& uv);

/// Pixel → undistorted sensor mm (closed form: pixel → distorted mm → eq. 7).
Eigen::Vector2d pixel_to_undistorted_sensor(const CameraIntrinsics& in, const Eigen::Vector2d& uv);

}  // namespace rangecal
