#include "optim/network/network_outliers.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "optim/bundle/whitening.hpp"
#include "optim/estimation/robust_scale.hpp"
#include "optim/estimation/symmetric_part.hpp"
#include "optim/network/network_covariance.hpp"

namespace rangecal {
namespace {

/// P(χ²_m > x) for m = 1, 2, 3 (Abramowitz & Stegun 26.4.4–26.4.5).
double chi2_survival(int m, double x) {
  constexpr double kPi = 3.14159265358979323846;
  if (m == 1) return std::erfc(std::sqrt(x / 2));
  if (m == 2) return std::exp(-x / 2);
  return std::erfc(std::sqrt(x / 2)) + std::sqrt(2 * x / kPi) * std::exp(-x / 2);
}

}  // namespace

double chi2_upper_quantile(int m, double alpha) {
  m = std::clamp(m, 1, 3);
  double lo = 0, hi = 1;
  while (chi2_survival(m, hi) > alpha) hi *= 2;
  for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (chi2_survival(m, mid) > alpha ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

std::vector<std::size_t> flag_ppk_outliers(const NetworkLayout& l, const NetworkParameterBlocks& b,
                                           double alpha, NetworkSelection* sel,
                                           std::vector<NetworkPointResult>* points) {
  std::vector<std::size_t> flagged;
  const double quantile[4] = {0, chi2_upper_quantile(1, alpha), chi2_upper_quantile(2, alpha),
                              chi2_upper_quantile(3, alpha)};
  for (std::size_t k = 0; k < l.by_point.size(); ++k) {
    const NetworkPoint& p = (*l.points)[k];
    if (p.control_pole || !sel->prior[k]) continue;
    const PointLinearisation lin = linearise_point(l, b, *sel, k, nullptr, nullptr, nullptr);
    if (lin.cameras < 2) continue;
    // Cov(X̂ − X̄) = Σ − (V_rays + Σ⁻¹)⁻¹ with Σ the fix's whole covariance. A white prior's V is
    // already V_rays + Σ⁻¹; a chained one's holds only its white part (lin.P), its fix weighed alone.
    const Eigen::Matrix3d& total = l.prior_total_cov[k];
    const Eigen::Matrix3d Sr = lin.P.isZero(0)
                                   ? Eigen::Matrix3d(total - lin.V.inverse())
                                   : Eigen::Matrix3d(total - (lin.V - lin.P + total.inverse()).inverse());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(symmetric_part(Sr));
    const Eigen::Vector3d r = Eigen::Map<const Eigen::Vector3d>(b.points[k].data()) - p.prior_enu;
    const double top = es.eigenvalues().maxCoeff();
    double d2 = 0;
    int m = 0;
    for (int a = 0; a < 3; ++a) {
      const double lam = es.eigenvalues()[a];
      if (!(lam > 1e-6 * top)) continue;
      const double z = es.eigenvectors().col(a).dot(r);
      d2 += z * z / lam, ++m;
    }
    NetworkPointResult& pr = (*points)[k];
    pr.ppk_test_d2 = d2, pr.ppk_test_dof = m;
    if (m > 0 && d2 > quantile[m]) {
      pr.ppk_outlier = true;
      sel->prior[k] = 0;
      flagged.push_back(k);
    }
  }
  return flagged;
}

ImageOutlierTest test_image_observations(const NetworkLayout& l, const NetworkParameterBlocks& b,
                                         const NetworkSelection& sel, double outlier_threshold) {
  const std::vector<NetworkObservation>& obs = *l.observations;
  const std::size_t n = obs.size(), nc = l.starts.size();
  ImageOutlierTest t;
  t.residual_px.assign(n, Eigen::Vector2d::Zero());
  t.whitened_norm.assign(n, 0);
  t.outlier.assign(n, false);
  t.threshold.assign(nc, 0);
  std::vector<Camera> cams(nc);
  for (std::size_t c = 0; c < nc; ++c) cams[c] = b.cameras[c].to_camera(l.starts[c]);
  // A point whose prior was dropped is referred to its rays: covariance V⁻¹ of the images alone.
  std::vector<Eigen::Matrix3d> ray_cov(l.by_point.size());
  for (std::size_t k = 0; k < l.by_point.size(); ++k)
    if (!sel.prior[k]) {
      const PointLinearisation lin = linearise_point(l, b, sel, k, nullptr, nullptr, nullptr);
      ray_cov[k] = lin.cameras >= 2 ? Eigen::Matrix3d(lin.V.inverse()) : Eigen::Matrix3d::Identity();
    }
  std::vector<std::vector<double>> norms(nc);
  for (std::size_t i = 0; i < n; ++i) {
    const NetworkObservation& o = obs[i];
    const NetworkPoint& p = (*l.points)[o.point];
    BundleObservation bo;
    const bool prior = sel.prior[o.point] != 0;
    const Eigen::Vector3d X =
        prior ? p.prior_enu : Eigen::Map<const Eigen::Vector3d>(b.points[o.point].data());
    bo.world = network_seen_point(X, o, b.cameras[o.camera].clock[0]);
    bo.world_cov = prior ? l.prior_total_cov[o.point] : ray_cov[o.point];
    Eigen::Vector2d uv;
    if (!project(cams[o.camera], bo.world, &uv)) uv.setConstant(std::numeric_limits<double>::infinity());
    t.residual_px[i] = uv - o.pixel;
    t.whitened_norm[i] = (whitening_matrix(cams[o.camera], bo, l.pixel_sigma(i)) * t.residual_px[i]).norm();
    if (sel.observation[i]) norms[o.camera].push_back(t.whitened_norm[i]);
  }
  for (std::size_t c = 0; c < nc; ++c) t.threshold[c] = robust_outlier_threshold(outlier_threshold, norms[c]);
  for (std::size_t i = 0; i < n; ++i) t.outlier[i] = !(t.whitened_norm[i] <= t.threshold[obs[i].camera]);
  return t;
}

}  // namespace rangecal
