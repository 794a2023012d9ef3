#include "pipeline/demo/demo_bars.hpp"

#include <fmt/format.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "optim/network/network_outliers.hpp"

namespace rangecal {
namespace {

std::vector<std::string> checked_methods(const DemoResults& r) {
  std::vector<std::string> m{"bundle"};
  if (r.method != "bundle") m.push_back(r.method);
  return m;
}

bool is_checked(const std::vector<std::string>& methods, const std::string& m) {
  return std::find(methods.begin(), methods.end(), m) != methods.end();
}

/// dᵀ·C⁻¹·d, or +∞ when C is not positive definite (no σ to test against).
double mahalanobis2(const Eigen::Vector3d& d, const Eigen::Matrix3d& c) {
  const Eigen::LLT<Eigen::Matrix3d> llt(c);
  if (llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  return d.dot(llt.solve(d));
}

void add_parameter_bars(const DemoResults& r, const std::vector<std::string>& methods, DemoBars* out) {
  for (const DemoCamera& c : r.cameras)
    for (const std::string& meth : methods)
      for (const ParameterCheck& p : parameter_checks(c, meth)) {
        const bool pass = p.sigma > 0 && std::abs(p.z()) <= out->parameter_z_limit;
        out->bars.push_back(
            {fmt::format("  {:<5} {:<7} {:<3} estimate {:.6g} truth {:.6g} sigma {:.3g} -> {:+.2f} sigma "
                         "(limit {:.2f})  {}",
                         c.id, meth, p.name, p.estimate, p.truth, p.sigma, p.z(), out->parameter_z_limit,
                         pass ? "ok" : "FAIL"),
             pass});
      }
}

void add_pole_bars(const DemoIntersection& d, DemoBars* out) {
  double worst = 0, largest_eigen = 0;
  std::string worst_id;
  for (const DemoIntersection::Pole& p : d.check_poles) {
    const double q = mahalanobis2(p.error_m, p.cov_m2);
    if (!(q <= worst)) worst = q, worst_id = p.id;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(p.cov_m2, Eigen::EigenvaluesOnly);
    largest_eigen = std::max(largest_eigen, eig.eigenvalues().maxCoeff());
  }
  const bool pass = d.n_check > 0 && worst <= out->pole_chi2_limit;
  out->bars.push_back(
      {fmt::format("  {:<7} check poles against truth: largest dT C^-1 d {:.2f} ({}) over {} poles "
                   "(limit {:.2f}, chi2 3 dof)  {}",
                   d.method, worst, worst_id, d.n_check, out->pole_chi2_limit, pass ? "ok" : "FAIL"),
       pass});
  // The absolute bar, where the predicted covariances make it one a correct calibration passes.
  const double needed = std::sqrt(largest_eigen * out->pole_chi2_limit);
  const bool applied = needed <= kDemoMeanDrBar_m;
  const bool abs_pass = !applied || (d.n_check > 0 && d.mean_dR_truth_m <= kDemoMeanDrBar_m);
  out->bars.push_back(
      {fmt::format("  {:<7} check-pole mean dR against truth {:.2f} cm over {} poles (bar {:.1f} cm)  {}",
                   d.method, 100 * d.mean_dR_truth_m, d.n_check, 100 * kDemoMeanDrBar_m,
                   !applied   ? fmt::format("not applied: the predicted sigma needs {:.2f} cm", 100 * needed)
                   : abs_pass ? "ok"
                              : "FAIL"),
       abs_pass});
}

}  // namespace

bool DemoBars::pass() const {
  return std::all_of(bars.begin(), bars.end(), [](const DemoBar& b) { return b.pass; });
}

DemoBars demo_accuracy_bars(const DemoResults& r) {
  const std::vector<std::string> methods = checked_methods(r);
  int n_parameters = 0, n_poles = 0;
  for (const DemoCamera& c : r.cameras)
    for (const std::string& meth : methods)
      n_parameters += static_cast<int>(parameter_checks(c, meth).size());
  for (const DemoIntersection& d : r.intersections)
    if (is_checked(methods, d.method)) n_poles += static_cast<int>(d.check_poles.size());
  DemoBars out;
  const double half = kDemoBarsAlpha / 2;
  out.parameter_z_limit = std::sqrt(chi2_upper_quantile(1, half / std::max(n_parameters, 1)));
  out.pole_chi2_limit = chi2_upper_quantile(3, half / std::max(n_poles, 1));
  add_parameter_bars(r, methods, &out);
  for (const DemoIntersection& d : r.intersections)
    if (is_checked(methods, d.method)) add_pole_bars(d, &out);
  return out;
}

}  // namespace rangecal
