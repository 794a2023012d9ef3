#include "support/correlated_crb.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "support/synthetic_camera.hpp"

namespace rangecal::test {
namespace {

using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::VectorXd;

[[noreturn]] void refuse(const std::string& why) {
  throw std::invalid_argument("correlated_crb: " + why);
}

bool supported(CameraParameter p) {
  return index_of(p) <= index_of(CameraParameter::a2) || is_rotation(p) || is_center(p);
}

/// The truth of camera `c` with its free parameters set to `x`: intrinsics and distortion as given,
/// R = exp([w]×)·R_true, centre C, T = −R·C (vision/camera/camera_parameters.hpp's convention, written
/// out here rather than taken from camera_with_parameters).
Camera camera_at(const CrbCamera& c, const VectorXd& x) {
  Camera cam = c.truth;
  std::array<double, 7> d = cam.intr.dist.as_array();
  Vector3d w = Vector3d::Zero(), C = c.truth.pose.center();
  for (std::size_t k = 0; k < c.free.size(); ++k) {
    const CameraParameter p = c.free[k];
    const double v = x[static_cast<Eigen::Index>(k)];
    if (p == CameraParameter::f) cam.intr.f_mm = v;
    if (p == CameraParameter::sx) cam.intr.sx = v;
    if (p == CameraParameter::u0) cam.intr.u0_px = v;
    if (p == CameraParameter::v0) cam.intr.v0_px = v;
    if (is_distortion(p)) d[static_cast<std::size_t>(index_of(p) - index_of(CameraParameter::k1))] = v;
    if (is_rotation(p)) w[index_of(p) - index_of(CameraParameter::wx)] = v;
    if (is_center(p)) C[index_of(p) - index_of(CameraParameter::CE)] = v;
  }
  cam.intr.dist = Distortion::from_array(d.data());
  const double a = w.norm();
  const Matrix3d Rw = a > 0 ? Matrix3d(Eigen::AngleAxisd(a, w / a)) : Matrix3d::Identity();
  cam.pose.R = Rw * c.truth.pose.R;
  cam.pose.T = -cam.pose.R * C;
  return cam;
}

/// Values of camera cc's free parameters of `cam` (rotations: the rotation vector of cam.R·R_trueᵀ).
VectorXd values_of(const CrbCamera& cc, const Camera& cam) {
  VectorXd v(static_cast<Eigen::Index>(cc.free.size()));
  const Eigen::AngleAxisd aa(Matrix3d(cam.pose.R * cc.truth.pose.R.transpose()));
  const Vector3d w = aa.angle() * aa.axis(), C = cam.pose.center();
  const std::array<double, 7> d = cam.intr.dist.as_array();
  for (std::size_t k = 0; k < cc.free.size(); ++k) {
    const CameraParameter p = cc.free[k];
    double x = 0;
    if (p == CameraParameter::f) x = cam.intr.f_mm;
    if (p == CameraParameter::sx) x = cam.intr.sx;
    if (p == CameraParameter::u0) x = cam.intr.u0_px;
    if (p == CameraParameter::v0) x = cam.intr.v0_px;
    if (is_distortion(p)) x = d[static_cast<std::size_t>(index_of(p) - index_of(CameraParameter::k1))];
    if (is_rotation(p)) x = w[index_of(p) - index_of(CameraParameter::wx)];
    if (is_center(p)) x = C[index_of(p) - index_of(CameraParameter::CE)];
    v[static_cast<Eigen::Index>(k)] = x;
  }
  return v;
}

/// Central-difference step of parameter p: a change that moves the image by ~1e-3 px.
double step(CameraParameter p, const CameraIntrinsics& in) {
  const double r = 0.5 * std::hypot(in.width_px * in.dx_mm, in.height_px * in.dy_mm);  // half-diagonal, mm
  switch (p) {
    case CameraParameter::f:
      return 1e-6 * in.f_mm;
    case CameraParameter::u0:
    case CameraParameter::v0:
      return 1e-3;
    case CameraParameter::k1:
      return 1e-6 / (r * r);
    case CameraParameter::k2:
      return 1e-6 / std::pow(r, 4);
    case CameraParameter::k3:
      return 1e-6 / std::pow(r, 6);
    case CameraParameter::p1:
    case CameraParameter::p2:
      return 1e-6 / r;
    default:
      return is_center(p) ? 1e-5 : 1e-6;  // m; sx, a1, a2, rad
  }
}
constexpr double kPointStep = 1e-5;  // m

Vector2d pixel(const Camera& cam, const Vector3d& X) {
  Vector2d uv;
  if (!project(cam, X, &uv)) refuse("a point does not project into " + cam.id);
  return uv;
}

/// ∂uv/∂θ_c (2 × free) and ∂uv/∂X (2 × 3) of camera c's truth at X, central differences.
void view_jacobian(const CrbCamera& c, const Vector3d& X, MatrixXd* Jc, Eigen::Matrix<double, 2, 3>* JX) {
  const VectorXd x0 = values_of(c, c.truth);
  Jc->resize(2, static_cast<Eigen::Index>(c.free.size()));
  for (Eigen::Index j = 0; j < x0.size(); ++j) {
    const double h = step(c.free[static_cast<std::size_t>(j)], c.truth.intr);
    VectorXd xp = x0, xm = x0;
    xp[j] += h, xm[j] -= h;
    Jc->col(j) = (pixel(camera_at(c, xp), X) - pixel(camera_at(c, xm), X)) / (2 * h);
  }
  for (int a = 0; a < 3; ++a) {
    const Vector3d e = Vector3d::Unit(a) * kPointStep;
    JX->col(a) = (pixel(c.truth, X + e) - pixel(c.truth, X - e)) / (2 * kPointStep);
  }
}

std::vector<int> camera_offsets(const CrbNetwork& n, int* total) {
  std::vector<int> off;
  *total = 0;
  for (const CrbCamera& c : n.cameras) {
    for (CameraParameter p : c.free)
      if (!supported(p)) refuse(std::string("free parameter ") + parameter_name(p) + " is not supported");
    off.push_back(*total);
    *total += static_cast<int>(c.free.size());
  }
  return off;
}

/// The Fisher information F of every parameter (cameras, epochs, poles) with the fixes' Σ_PPK⁻¹.
MatrixXd information(const CrbNetwork& n, const PpkJointCovariance& ppk, const std::vector<int>& off, int P) {
  const Eigen::Index ne = static_cast<Eigen::Index>(n.epochs.size());
  const Eigen::Index np = static_cast<Eigen::Index>(n.poles.size());
  if (ppk.information.rows() != 3 * ne || n.epoch_time_s.size() != n.epochs.size())
    refuse("Σ_PPK or the epoch times do not match the epochs");
  const Eigen::Index dim = P + 3 * (ne + np);
  MatrixXd F = MatrixXd::Zero(dim, dim);
  MatrixXd Jc;
  Eigen::Matrix<double, 2, 3> JX;
  for (const CrbView& v : n.views) {
    if (v.camera >= n.cameras.size() || v.point >= n.epochs.size() + n.poles.size())
      refuse("view out of range");
    const Eigen::Index k = static_cast<Eigen::Index>(v.point);
    const Vector3d X = k < ne ? n.epochs[v.point] : n.poles[v.point - n.epochs.size()];
    const CrbCamera& c = n.cameras[v.camera];
    view_jacobian(c, X, &Jc, &JX);
    const double w = 1 / (v.pixel_sigma_px * v.pixel_sigma_px);
    const Eigen::Index o = off[v.camera], p = Jc.cols(), q = P + 3 * k;
    F.block(o, o, p, p) += w * Jc.transpose() * Jc;
    F.block(o, q, p, 3) += w * Jc.transpose() * JX;
    F.block(q, o, 3, p) += w * JX.transpose() * Jc;
    F.block(q, q, 3, 3) += w * JX.transpose() * JX;
  }
  F.block(P, P, 3 * ne, 3 * ne) += ppk.information;
  for (Eigen::Index j = 0; j < np; ++j)
    F.block(P + 3 * (ne + j), P + 3 * (ne + j), 3, 3) +=
        Matrix3d::Identity() / (n.pole_sigma_m * n.pole_sigma_m);
  for (std::size_t c = 0; c < n.cameras.size(); ++c) {
    const double s = n.cameras[c].station_sigma_m;
    if (!(s > 0)) continue;
    for (std::size_t k = 0; k < n.cameras[c].free.size(); ++k)
      if (is_center(n.cameras[c].free[k]))
        F(off[c] + static_cast<int>(k), off[c] + static_cast<int>(k)) += 1 / (s * s);
  }
  return F;
}

/// The first P columns of F⁻¹ (Jacobi-scaled Cholesky): the cameras' rows of the inverse.
MatrixXd inverse_camera_columns(const MatrixXd& F, int P) {
  const VectorXd d = F.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const MatrixXd Fs = d.asDiagonal() * F * d.asDiagonal();
  const Eigen::LLT<MatrixXd> llt(Fs);
  if (llt.info() != Eigen::Success || !(llt.rcond() > 1e-15)) refuse("the Fisher information is singular");
  MatrixXd E = MatrixXd::Zero(F.rows(), P);
  for (int j = 0; j < P; ++j) E(j, j) = d[j];
  return d.asDiagonal() * llt.solve(E);
}

}  // namespace

GaussMarkovPpk GaussMarkovPpk::as_white() const {
  const Eigen::Vector3d s = total_sigma();
  GaussMarkovPpk w;
  w.white_h_m = s.x(), w.white_v_m = s.z();
  return w;
}

Eigen::Vector3d GaussMarkovPpk::total_sigma() const {
  const double h = std::hypot(white_h_m, gm_h_m), v = std::hypot(white_v_m, gm_v_m);
  return {h, h, v};
}

GaussMarkovPpk measured_ppk_model(double tau_s) {
  GaussMarkovPpk m;
  m.white_h_m = 0.003, m.white_v_m = 0.005;
  m.gm_h_m = 0.008, m.gm_v_m = 0.014;
  m.tau_h_s = tau_s, m.tau_v_s = tau_s;
  return m;
}

PpkJointCovariance ppk_joint_covariance(const std::vector<double>& t, const GaussMarkovPpk& m) {
  if (t.size() > kMaxCrbEpochs)
    refuse(std::to_string(t.size()) + " epochs: the dense Σ_PPK is limited to " +
           std::to_string(kMaxCrbEpochs));
  const Eigen::Index N = static_cast<Eigen::Index>(t.size());
  PpkJointCovariance out;
  out.cov = MatrixXd::Zero(3 * N, 3 * N);
  out.information = MatrixXd::Zero(3 * N, 3 * N);
  // The axes are uncorrelated, so Σ_PPK⁻¹ is each axis's N × N block inverted (Cholesky) and put back
  // in place: a third of the work of one 3N × 3N factorisation, ninefold less.
  for (int a = 0; a < 3; ++a) {
    const double sw = a < 2 ? m.white_h_m : m.white_v_m, sg = a < 2 ? m.gm_h_m : m.gm_v_m;
    const double tau = a < 2 ? m.tau_h_s : m.tau_v_s;
    MatrixXd C(N, N);
    for (Eigen::Index i = 0; i < N; ++i)
      for (Eigen::Index j = 0; j < N; ++j) {
        const double dt = std::abs(t[static_cast<std::size_t>(i)] - t[static_cast<std::size_t>(j)]);
        const double rho = tau > 0 ? std::exp(-dt / tau) : (i == j ? 1.0 : 0.0);
        C(i, j) = sg * sg * rho + (i == j ? sw * sw : 0.0);
      }
    const Eigen::LLT<MatrixXd> llt(C);
    if (llt.info() != Eigen::Success) refuse("Σ_PPK is not positive definite");
    MatrixXd Ci = llt.solve(MatrixXd::Identity(N, N));
    Ci = 0.5 * (Ci + Ci.transpose()).eval();
    for (Eigen::Index i = 0; i < N; ++i)
      for (Eigen::Index j = 0; j < N; ++j) {
        out.cov(3 * i + a, 3 * j + a) = C(i, j);
        out.information(3 * i + a, 3 * j + a) = Ci(i, j);
      }
  }
  return out;
}

std::vector<Eigen::Vector3d> draw_correlated_ppk_errors(const std::vector<double>& t, const GaussMarkovPpk& m,
                                                        DeterministicRandom* rng) {
  std::vector<Vector3d> e(t.size());
  Vector3d g = Vector3d::Zero();
  for (std::size_t k = 0; k < t.size(); ++k)
    for (int a = 0; a < 3; ++a) {
      const double sw = a < 2 ? m.white_h_m : m.white_v_m, sg = a < 2 ? m.gm_h_m : m.gm_v_m;
      const double tau = a < 2 ? m.tau_h_s : m.tau_v_s;
      const double phi = k > 0 && tau > 0 ? std::exp(-(t[k] - t[k - 1]) / tau) : 0.0;
      g[a] = phi * g[a] + sg * std::sqrt(1 - phi * phi) * rng->normal();
      e[k][a] = g[a] + sw * rng->normal();
    }
  return e;
}

Eigen::VectorXd CameraJointCovariance::sigma(std::size_t c) const {
  const int end = c + 1 < offset.size() ? offset[c + 1] : static_cast<int>(joint.rows());
  return joint.diagonal().segment(offset[c], end - offset[c]).cwiseSqrt();
}

CameraJointCovariance cramer_rao_bound(const CrbNetwork& n, const PpkJointCovariance& ppk) {
  CameraJointCovariance out;
  int P = 0;
  out.offset = camera_offsets(n, &P);
  out.joint = inverse_camera_columns(information(n, ppk, out.offset, P), P).topRows(P);
  out.joint = 0.5 * (out.joint + out.joint.transpose()).eval();
  return out;
}

CameraJointCovariance sandwich_covariance(const CrbNetwork& n, const PpkJointCovariance& assumed,
                                          const PpkJointCovariance& truth) {
  CameraJointCovariance out;
  int P = 0;
  out.offset = camera_offsets(n, &P);
  const MatrixXd G = inverse_camera_columns(information(n, assumed, out.offset, P), P);
  const Eigen::Index ne3 = 3 * static_cast<Eigen::Index>(n.epochs.size());
  // H = [F_a⁻¹]_cameras,epochs · Σ_a⁻¹ (F_a⁻¹ symmetric: its epochs' rows of the camera columns, transposed).
  const MatrixXd H = G.middleRows(P, ne3).transpose() * assumed.information;
  out.joint = G.topRows(P) + H * (truth.cov - assumed.cov) * H.transpose();
  out.joint = 0.5 * (out.joint + out.joint.transpose()).eval();
  return out;
}

std::vector<Eigen::Vector3d> flight_volume(const CrbNetwork& n, int count, std::uint64_t seed) {
  Vector3d lo = Vector3d::Constant(1e300), hi = Vector3d::Constant(-1e300);
  for (const Vector3d& X : n.epochs) lo = lo.cwiseMin(X), hi = hi.cwiseMax(X);
  DeterministicRandom rng(seed);
  std::vector<Vector3d> out;
  for (int draw = 0; draw < 100 * count && static_cast<int>(out.size()) < count; ++draw) {
    Vector3d X;
    for (int a = 0; a < 3; ++a) X[a] = rng.uniform(lo[a], hi[a]);
    int seen = 0;
    for (const CrbCamera& c : n.cameras) {
      Vector2d uv;
      if (project(c.truth, X, &uv) && inside_image(c.truth.intr, uv)) ++seen;
    }
    if (seen >= 2) out.push_back(X);
  }
  return out;
}

double intersection_sigma_m(const CrbNetwork& n, const CameraJointCovariance& cov,
                            const std::vector<Eigen::Vector3d>& points) {
  const Eigen::Index P = cov.joint.rows();
  double sum = 0;
  int used = 0;
  MatrixXd Jc;
  Eigen::Matrix<double, 2, 3> JX;
  for (const Vector3d& X : points) {
    std::vector<std::size_t> seen;
    for (std::size_t c = 0; c < n.cameras.size(); ++c) {
      Vector2d uv;
      if (project(n.cameras[c].truth, X, &uv) && inside_image(n.cameras[c].truth.intr, uv)) seen.push_back(c);
    }
    if (seen.size() < 2) continue;
    const Eigen::Index m = static_cast<Eigen::Index>(seen.size());
    MatrixXd AX(2 * m, 3), AT = MatrixXd::Zero(2 * m, P);
    for (Eigen::Index i = 0; i < m; ++i) {
      const std::size_t c = seen[static_cast<std::size_t>(i)];
      view_jacobian(n.cameras[c], X, &Jc, &JX);
      AX.middleRows(2 * i, 2) = JX;
      AT.block(2 * i, cov.offset[c], 2, Jc.cols()) = Jc;
    }
    const MatrixXd K = (AX.transpose() * AX).ldlt().solve(AX.transpose() * AT);  // J_X⁺·J_θ
    sum += (K * cov.joint * K.transpose()).trace();
    ++used;
  }
  if (used == 0) refuse("no point of the flight volume is seen by two cameras");
  return std::sqrt(sum / used);
}

CrbNetwork ascent_network(const AscentNetworkOptions& o) {
  const Vector3d aim(0, 2.5, 5.3);
  const Vector3d centres[2] = {{-38, -33, 1.5}, {52, -52, 1.8}};
  const Eigen::Vector2d ascents[5] = {{-5, 0.75}, {0, 4.75}, {5, 0.75}, {0, -3.25}, {0, 8.75}};
  const Vector3d poles[2] = {{-2, -1, 2.2}, {2, -1, 7.5}};
  CrbNetwork n;
  for (int c = 0; c < 2; ++c) {
    CrbCamera cam;
    cam.truth = range_camera_at("cam" + std::to_string(c + 1), centres[c], aim);
    cam.truth.intr.f_mm = 100;
    cam.free = expand_free_parameters({"f", "k1", "pose"});
    cam.station_sigma_m = o.station_sigma_m;
    n.cameras.push_back(cam);
  }
  auto seen_by = [&](const Vector3d& X) {
    std::vector<std::size_t> s;
    for (std::size_t c = 0; c < n.cameras.size(); ++c) {
      Vector2d uv;
      if (project(n.cameras[c].truth, X, &uv) && inside_image(n.cameras[c].truth.intr, uv)) s.push_back(c);
    }
    return s;
  };
  const int per_climb = static_cast<int>(std::floor(o.climb_s * o.rate_hz)) + 1;
  for (int a = 0; a < std::min(o.ascents, 5); ++a)
    for (int i = 0; i < per_climb; ++i) {
      const double dt = i / o.rate_hz;
      const Vector3d X(ascents[a].x(), ascents[a].y(), 0.8 + 9.0 * dt / o.climb_s);
      const std::vector<std::size_t> s = seen_by(X);
      if (s.empty()) continue;
      for (std::size_t c : s) n.views.push_back({c, n.epochs.size(), o.pixel_sigma_px});
      n.epochs.push_back(X);
      n.epoch_time_s.push_back(a * (o.climb_s + o.transit_s) + dt);
    }
  n.pole_sigma_m = o.pole_sigma_m;
  for (int j = 0; j < std::min(o.control_poles, 2); ++j) {
    for (std::size_t c : seen_by(poles[j]))
      n.views.push_back({c, n.epochs.size() + n.poles.size(), o.pick_sigma_px});
    n.poles.push_back(poles[j]);
  }
  return n;
}

namespace {

/// calibrate.free names of a free set: single names, and the pose as the groups "rotation" and "center".
std::vector<std::string> free_names(const std::vector<CameraParameter>& free) {
  std::vector<std::string> names;
  int rot = 0, cen = 0;
  for (CameraParameter p : free) {
    if (is_rotation(p))
      ++rot;
    else if (is_center(p))
      ++cen;
    else
      names.push_back(parameter_name(p));
  }
  if (rot % 3 != 0 || cen % 3 != 0) refuse("a partial rotation or centre cannot be named to the network");
  if (rot) names.push_back("rotation");
  if (cen) names.push_back("center");
  return names;
}

}  // namespace

NetworkInput network_input(const CrbNetwork& n, const GaussMarkovPpk& weights, const NetworkNoise& noise,
                           const std::vector<Camera>& start) {
  NetworkInput in;
  for (std::size_t c = 0; c < n.cameras.size(); ++c) {
    const CrbCamera& cc = n.cameras[c];
    NetworkCamera nc;
    nc.initial = start.empty() ? cc.truth : start[c];
    nc.options.free = free_names(cc.free);
    nc.options.scale_covariance = false;
    if (cc.station_sigma_m > 0) {
      nc.options.priors.use_center = true;
      nc.options.priors.center_enu_m =
          cc.truth.pose.center() + (noise.station_error.empty() ? Vector3d::Zero() : noise.station_error[c]);
      nc.options.priors.center_sigma_m = Vector3d::Constant(cc.station_sigma_m);
    }
    in.cameras.push_back(nc);
  }
  // A camera's lamp centroids at its default σ (its first lamp view's), as the pipeline gives them
  // (pipeline/steps/network_problem.cpp): the network's image variance component scales them;
  // another σ (a pole pick's) stays the observation's own.
  std::vector<char> has_default(n.cameras.size(), 0);
  for (const CrbView& v : n.views)
    if (v.point < n.epochs.size() && !has_default[v.camera])
      in.cameras[v.camera].options.pixel_sigma_px = v.pixel_sigma_px, has_default[v.camera] = 1;
  const Vector3d s = weights.total_sigma();
  for (std::size_t k = 0; k < n.epochs.size(); ++k) {
    NetworkPoint p;
    p.prior_enu = n.epochs[k] + (noise.ppk_error.empty() ? Vector3d::Zero() : noise.ppk_error[k]);
    p.prior_cov = s.cwiseProduct(s).asDiagonal();
    p.time_s = n.epoch_time_s[k];
    p.source = "epoch " + std::to_string(k);
    in.points.push_back(p);
  }
  for (std::size_t j = 0; j < n.poles.size(); ++j) {
    NetworkPoint p;
    p.prior_enu = n.poles[j] + (noise.pole_error.empty() ? Vector3d::Zero() : noise.pole_error[j]);
    p.prior_cov = Matrix3d::Identity() * n.pole_sigma_m * n.pole_sigma_m;
    p.control_pole = true;
    p.quality = 0;
    p.source = "pole " + std::to_string(j);
    in.points.push_back(p);
  }
  for (std::size_t i = 0; i < n.views.size(); ++i) {
    const CrbView& v = n.views[i];
    const Vector3d X = v.point < n.epochs.size() ? n.epochs[v.point] : n.poles[v.point - n.epochs.size()];
    NetworkObservation ob;
    ob.camera = v.camera;
    ob.point = v.point;
    ob.pixel = pixel(n.cameras[v.camera].truth, X) +
               (noise.pixel_noise.empty() ? Vector2d::Zero() : noise.pixel_noise[i]);
    const bool centroid =
        v.point < n.epochs.size() && v.pixel_sigma_px == in.cameras[v.camera].options.pixel_sigma_px;
    ob.pixel_sigma_px = centroid ? 0 : v.pixel_sigma_px;
    in.observations.push_back(ob);
  }
  return in;
}

Eigen::VectorXd free_values(const CrbNetwork& n, std::size_t c, const Camera& cam) {
  return values_of(n.cameras[c], cam);
}

CrbNetwork one_camera(const CrbNetwork& n) {
  CrbNetwork one;
  one.cameras = {n.cameras[0]};
  for (const CrbView& v : n.views) {
    if (v.camera != 0 || v.point >= n.epochs.size()) continue;
    one.views.push_back({0, one.epochs.size(), v.pixel_sigma_px});
    one.epochs.push_back(n.epochs[v.point]);
    one.epoch_time_s.push_back(n.epoch_time_s[v.point]);
  }
  return one;
}

PpkErrorModel network_model(const GaussMarkovPpk& m) {
  const Eigen::Vector3d total = m.total_sigma();
  PpkErrorModel e;
  e.white_scale_h = m.white_h_m / total.x(), e.white_scale_v = m.white_v_m / total.z();
  e.gm_sd_h_m = m.gm_h_m, e.gm_sd_v_m = m.gm_v_m;
  e.tau_h_s = m.tau_h_s, e.tau_v_s = m.tau_v_s;
  return e;
}

NetworkOptions plain_least_squares_network() {
  NetworkOptions opt;
  opt.loss = RobustLoss::none;
  opt.resolve_without_outliers = false;
  opt.ppk_outlier_probability = 1e-300;
  return opt;
}

NetworkNoise draw_network_noise(const CrbNetwork& n, const GaussMarkovPpk& model, DeterministicRandom* rng) {
  NetworkNoise noise;
  noise.ppk_error = draw_correlated_ppk_errors(n.epoch_time_s, model, rng);
  const auto normal3 = [&]() { return Eigen::Vector3d(rng->normal(), rng->normal(), rng->normal()); };
  for (std::size_t j = 0; j < n.poles.size(); ++j) noise.pole_error.push_back(n.pole_sigma_m * normal3());
  for (const CrbCamera& c : n.cameras) noise.station_error.push_back(c.station_sigma_m * normal3());
  for (const CrbView& v : n.views)
    noise.pixel_noise.push_back(v.pixel_sigma_px * Eigen::Vector2d(rng->normal(), rng->normal()));
  return noise;
}

}  // namespace rangecal::test
