#include "optim/methods/tsai_sassa.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "config/error.hpp"
#include "optim/estimation/reprojection_stats.hpp"

namespace rangecal {
namespace {

using Eigen::VectorXd;

constexpr double kInf = std::numeric_limits<double>::infinity();
using P = CameraParameter;
// θ: seed 002 §3.2.3's (f, Tz, k1), or with all_parameters every parameter of the model in Tsai's
// translation form (seed 002 Table 1 moved u0, v0 and sx too).
const std::vector<CameraParameter> kSearched3 = {P::f, P::Tz, P::k1};
const std::vector<CameraParameter> kSearchedAll = {P::f,  P::Tz, P::k1, P::sx, P::u0, P::v0,
                                                   P::wx, P::wy, P::wz, P::Tx, P::Ty};

bool reprojection_residual(const std::vector<PointCorrespondence>& pts, const Camera& cam, VectorXd* r) {
  r->resize(2 * pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    Eigen::Vector2d uv;
    if (!project(cam, pts[i].world, &uv)) return false;
    r->segment<2>(2 * i) = uv - pts[i].pixel;
  }
  return true;
}

/// Residual vector of the objective at θ (eq. 13 sensor mm, or pixels with all parameters).
bool objective_residual(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                        const TsaiStep1& s1, const VectorXd& th, VectorXd* r) {
  if (th.size() == 3) {
    // Behind the camera (Zc ≤ 0) the eq. 13 ratio is meaningless: infeasible.
    for (const auto& p : pts)
      if (!(s1.R.row(2).dot(p.world) + th[1] > 0)) return false;
    tsai_eq13_cost(pts, sensor, s1, th[0], th[1], th[2], r);
    return r->allFinite();
  }
  return reprojection_residual(pts, tsai_sassa_camera(sensor, s1, th), r);
}

double rms_px(const std::vector<PointCorrespondence>& pts, const Camera& cam) {
  VectorXd r;
  if (!reprojection_residual(pts, cam, &r)) return kInf;
  return std::sqrt(r.squaredNorm() / static_cast<double>(pts.size()));
}

}  // namespace

Camera tsai_sassa_camera(const TsaiSensor& sensor, const TsaiStep1& s1, const VectorXd& th) {
  const Camera c = tsai_camera(sensor, s1, th[0], th[1], th[2]);
  if (th.size() != static_cast<Eigen::Index>(kSearchedAll.size())) return c;
  return camera_with_parameters(c, kSearchedAll, th);
}

double tsai_sassa_objective(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                            const TsaiStep1& s1, const VectorXd& th) {
  VectorXd r;
  if (!objective_residual(pts, sensor, s1, th, &r)) return kInf;
  return r.squaredNorm();
}

VectorXd tsai_sassa_default_half_range(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                                       const TsaiStep1& step1, const VectorXd& th0) {
  double depth = 0;
  for (const auto& p : pts)
    depth += std::abs(step1.R.row(2).dot(p.world) + th0[1]) / static_cast<double>(pts.size());
  const double rmax = 0.5 * std::hypot(sensor.width_px * sensor.dx_mm, sensor.height_px * sensor.dy_mm);
  VectorXd S(th0.size());
  S[0] = 0.2 * std::abs(th0[0]);
  S[1] = 0.2 * std::max(depth, std::abs(th0[1]));
  S[2] = 0.05 / (rmax * rmax);
  if (th0.size() == static_cast<Eigen::Index>(kSearchedAll.size())) {
    const double tn = std::max(0.5, 0.02 * std::sqrt(th0[9] * th0[9] + th0[10] * th0[10] + th0[1] * th0[1]));
    S[3] = 0.02, S[4] = 20, S[5] = 20, S[6] = S[7] = S[8] = 5e-3, S[9] = tn, S[10] = tn;
  }
  return S;
}

TsaiSassaResult tsai_sassa_from(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                                const TsaiStep1& step1, const VectorXd& theta0, const TsaiSassaOptions& opt) {
  const Eigen::Index d = theta0.size();
  if (d != 3 && d != static_cast<Eigen::Index>(kSearchedAll.size()))
    throw_calibration_error("tsai_sassa", "θ0 must hold 3 (f, Tz, k1) or 11 parameters");
  TsaiSassaResult res;
  res.step1 = step1;
  res.parameters = d == 3 ? kSearched3 : kSearchedAll;
  res.theta0 = theta0;
  res.half_range =
      opt.half_range.size() ? opt.half_range : tsai_sassa_default_half_range(pts, sensor, step1, theta0);
  if (res.half_range.size() != d)
    throw_calibration_error("tsai_sassa.half_range", "wrong number of half-ranges");

  const ObjectiveFunction f = [&](const VectorXd& th) {
    return tsai_sassa_objective(pts, sensor, step1, th);
  };
  res.search = normalised_sparrow_search(f, theta0, res.half_range, opt.search);
  if (!std::isfinite(res.search.f))
    throw_calibration_error("tsai_sassa",
                            "the sparrow search found no feasible camera (every point behind it)");
  res.camera_search = tsai_sassa_camera(sensor, step1, res.search.theta);
  res.search_rms_px = rms_px(pts, res.camera_search);
  res.theta_polished = res.search.theta;
  res.camera = res.camera_search;

  if (opt.polish) {
    // LM on z (θ = θ0 + S·z) so μ·I is scaled alike in every coordinate.
    const ResidualFunction rz = [&](const VectorXd& z, VectorXd* r) {
      return objective_residual(pts, sensor, step1, theta0 + res.half_range.cwiseProduct(z), r);
    };
    res.polish = lm_qn_minimise(rz, nullptr, res.search.z, opt.polish_options);
    res.polished = true;
    res.theta_polished = theta0 + res.half_range.cwiseProduct(res.polish.x);
    res.camera = tsai_sassa_camera(sensor, step1, res.theta_polished);
  }

  auto& cal = res.calibration;
  cal.method = "tsai_sassa";
  VectorXd r;
  if (!reprojection_residual(pts, res.camera, &r)) {
    // The objective (eq. 13 over sensor mm) does not see a distortion that fails to invert over the
    // image: the last camera that projects every point is kept — the search's, else θ0 with k1 = 0
    // (every point in front of it, tsai_f_tz_start) — and the result says so.
    VectorXd th = theta0;
    th[2] = 0;
    const bool search_ok = opt.polish && reprojection_residual(pts, res.camera_search, &r);
    res.camera = search_ok ? res.camera_search : tsai_sassa_camera(sensor, step1, th);
    res.warnings.push_back({CalibrationWarningKind::projection_fallback,
                            {},
                            std::string("the ") + (opt.polish ? "polished" : "searched") +
                                " camera does not project every point (its distortion does not invert over "
                                "them); kept " +
                                (search_ok ? "the search's camera" : "the start θ0 with k1 = 0")});
  }
  cal.camera = res.camera;
  if (reprojection_residual(pts, res.camera, &r)) {
    std::vector<Eigen::Vector2d> residual_px(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i)
      residual_px[i] = r.segment<2>(2 * static_cast<Eigen::Index>(i));
    cal.reprojection = reprojection_stats(residual_px, std::vector<char>(pts.size(), 1));
  }
  cal.reprojection.n_used = static_cast<int>(pts.size());
  for (Eigen::Index j = 0; j < d; ++j)
    if (std::abs(res.search.z[j]) > 0.98)
      res.warnings.push_back({CalibrationWarningKind::search_at_range_edge,
                              {res.parameters[std::size_t(j)]},
                              "the sparrow search ended at the edge of its range in " +
                                  std::string(parameter_name(res.parameters[std::size_t(j)])) +
                                  " (|z| > 0.98): the half-range S is too narrow or θ0 too far off"});
  if (opt.polish && !res.polish.converged)
    res.warnings.push_back({CalibrationWarningKind::polish_not_converged,
                            {},
                            "the LM polish stopped without converging (" + res.polish.stop_reason + ")"});
  cal.warnings = warning_texts(res.warnings);

  return res;
}

TsaiSassaResult tsai_sassa_calibrate(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                                     const TsaiSassaOptions& opt) {
  TsaiStep1 s1 = tsai_step1(pts, sensor);
  // Tsai's linear f, Tz; on the f–distance ridge of a narrow field the lens's nominal f instead
  // (vision/calibration/tsai.hpp tsai_f_tz_start).
  const TsaiStart start = tsai_f_tz_start(pts, sensor, &s1, opt.nominal_f_mm);
  const double f0 = start.f_mm, Tz0 = start.Tz;
  VectorXd th0;
  if (opt.all_parameters) {
    th0.resize(static_cast<Eigen::Index>(kSearchedAll.size()));
    th0 << f0, Tz0, 0, s1.sx, s1.u0_px, s1.v0_px, 0, 0, 0, s1.Tx, s1.Ty;
  } else {
    th0 = (VectorXd(3) << f0, Tz0, 0.0).finished();
  }
  TsaiSassaResult res = tsai_sassa_from(pts, sensor, s1, th0, opt);
  res.start = start;
  return res;
}

}  // namespace rangecal
