#include "pipeline/report/trajectory_summary.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "optim/estimation/nearest_rank_quantile.hpp"

namespace rangecal {
namespace {

double quantile(const std::vector<double>& v, double q) {
  return nearest_rank_quantile(v, q, 0);
}

TrajectoryCameraUse& use_of(const std::string& id, std::vector<TrajectoryCameraUse>* uses) {
  for (TrajectoryCameraUse& u : *uses)
    if (u.id == id) return u;
  uses->push_back({id, 0, 0});
  return uses->back();
}

}  // namespace

TrajectorySummary summarise_trajectory(const std::vector<TrajectoryRow>& rows) {
  TrajectorySummary s;
  if (rows.empty()) return s;
  s.instants = static_cast<int>(rows.size());
  const auto since = [&](const TrajectoryRow& r) { return seconds_between(rows.front().utc, r.utc); };
  s.span_s = since(rows.back());
  std::vector<double> steps, sigma, labels, timing, calibration;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const TrajectoryRow& r = rows[k];
    if (k > 0) steps.push_back(since(r) - since(rows[k - 1]));
    sigma.push_back(r.sigma_m), labels.push_back(r.sigma_labels_m), timing.push_back(r.sigma_timing_m),
        calibration.push_back(r.sigma_calibration_m);
    s.inflated += r.inflated ? 1 : 0;
    s.extrapolated += r.extrapolated.empty() ? 0 : 1;
    for (const std::string& id : r.cameras) {
      TrajectoryCameraUse& u = use_of(id, &s.cameras);
      ++u.instants;
      if (std::find(r.extrapolated.begin(), r.extrapolated.end(), id) != r.extrapolated.end())
        ++u.extrapolated;
    }
  }
  s.step_s = quantile(steps, 0.5);
  s.sigma_median_m = quantile(sigma, 0.5);
  s.sigma_p95_m = quantile(sigma, 0.95);
  s.labels_median_m = quantile(labels, 0.5);
  s.timing_median_m = quantile(timing, 0.5);
  s.calibration_median_m = quantile(calibration, 0.5);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const bool gap = k > 0 && since(rows[k]) - since(rows[k - 1]) > kTrajectoryGapSteps * s.step_s;
    if (k == 0 || gap || rows[k].cameras != s.stretches.back().cameras)
      s.stretches.push_back({since(rows[k]), since(rows[k]), rows[k].cameras, 0});
    s.stretches.back().end_s = since(rows[k]);
    ++s.stretches.back().instants;
  }
  return s;
}

SigmaEllipse sigma_ellipse(const Eigen::Matrix2d& cov_m2) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov_m2);
  const Eigen::Vector2d sd = es.eigenvalues().cwiseMax(0).cwiseSqrt();
  Eigen::Vector2d major = es.eigenvectors().col(1);
  if (major.x() < 0 || (major.x() == 0 && major.y() < 0)) major = -major;
  return {sd[1], sd[0], std::atan2(major.y(), major.x()) * 180 / M_PI};
}

}  // namespace rangecal
