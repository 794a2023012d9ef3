#include "optim/network/image_time_correlation.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "vision/camera/camera_model.hpp"

namespace rangecal {
namespace {

struct TimedResidual {
  double t = 0;
  double du = 0, dv = 0;
};

/// Step of the central difference for ∂(pixels)/∂X (m): small against any range, large against
/// rounding at ENU magnitudes of kilometres.
constexpr double kPointStepM = 1e-4;

/// Median step between consecutive times (s); 0 when fewer than two.
double median_step(const std::vector<TimedResidual>& r) {
  std::vector<double> steps;
  for (std::size_t i = 1; i < r.size(); ++i) steps.push_back(r[i].t - r[i - 1].t);
  if (steps.empty()) return 0;
  std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
  return steps[steps.size() / 2];
}

/// F of one axis: the window's 1 + 2 Σ (1 − k/(K+1)) ρ_k or the AR(1)'s (1 + ρ_1)/(1 − ρ_1), the larger;
/// a lag-k pair counts only inside k + kLagGapTolerance steps.
double inflation(const std::vector<TimedResidual>& r, double TimedResidual::*axis, double step) {
  const std::size_t n = r.size();
  double mean = 0;
  for (const TimedResidual& x : r) mean += x.*axis;
  mean /= static_cast<double>(n);
  double var = 0;
  for (const TimedResidual& x : r) var += (x.*axis - mean) * (x.*axis - mean);
  var /= static_cast<double>(n);
  if (!(var > 0)) return 1;
  double f = 1, ar1 = 1;
  for (std::size_t k = 1; k <= static_cast<std::size_t>(kCorrelationLags); ++k) {
    double sum = 0;
    std::size_t pairs = 0;
    for (std::size_t i = 0; i + k < n; ++i) {
      if (r[i + k].t - r[i].t > (static_cast<double>(k) + kLagGapTolerance) * step) continue;
      sum += (r[i].*axis - mean) * (r[i + k].*axis - mean);
      ++pairs;
    }
    if (pairs == 0) continue;
    const double rho = sum / static_cast<double>(pairs) / var;
    f += 2 * (1 - static_cast<double>(k) / (kCorrelationLags + 1)) * rho;
    if (k == 1 && rho > 0 && rho < 1) ar1 = (1 + rho) / (1 - rho);
  }
  return std::max(f, ar1);
}

/// One used observation of a point: its camera, its residual's place in that camera's result.
struct Seen {
  std::size_t camera = 0, index = 0, observation = 0;
};

/// ∂(pixels)/∂X of camera c at the point X seen by observation o (px/m), by central differences;
/// false when a step leaves the camera's image model.
bool point_jacobian(const Camera& cam, const Eigen::Vector3d& X_seen, Eigen::Matrix<double, 2, 3>* J) {
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3d dx = Eigen::Vector3d::Zero();
    dx[a] = kPointStepM;
    Eigen::Vector2d plus, minus;
    if (!project(cam, X_seen + dx, &plus) || !project(cam, X_seen - dx, &minus)) return false;
    J->col(a) = (plus - minus) / (2 * kPointStepM);
  }
  return true;
}

/// Each camera's series: at every timed point seen by ≥ 2 cameras, the whitened residuals with the
/// point's directions projected out (in units of the camera's σ).
std::vector<std::vector<TimedResidual>> residuals_off_the_point(
    const NetworkResult& result, const std::vector<NetworkPoint>& points,
    const std::vector<NetworkObservation>& observations) {
  std::vector<std::vector<Seen>> by_point(points.size());
  for (std::size_t c = 0; c < result.cameras.size(); ++c) {
    const BundleResult& cam = result.cameras[c];
    const std::vector<std::size_t>& obs = result.camera_observations[c];
    for (std::size_t j = 0; j < obs.size() && j < cam.residual_px.size(); ++j) {
      if (j < cam.outlier.size() && cam.outlier[j]) continue;
      const std::size_t p = observations[obs[j]].point;
      if (std::isfinite(points[p].time_s) && p < result.points.size() && result.points[p].used)
        by_point[p].push_back({c, j, obs[j]});
    }
  }
  std::vector<std::vector<TimedResidual>> series(result.cameras.size());
  for (std::size_t p = 0; p < points.size(); ++p) {
    const std::vector<Seen>& seen = by_point[p];
    if (seen.size() < 2) continue;
    const auto m = static_cast<Eigen::Index>(2 * seen.size());
    Eigen::MatrixXd J(m, 3);
    Eigen::VectorXd r(m);
    bool ok = true;
    for (std::size_t i = 0; i < seen.size() && ok; ++i) {
      const BundleResult& b = result.cameras[seen[i].camera];
      const NetworkObservation& o = observations[seen[i].observation];
      const double w = 1 / b.details.pixel_sigma_px;
      Eigen::Matrix<double, 2, 3> Ji;
      ok = w > 0 &&
           point_jacobian(b.calibration.camera,
                          network_seen_point(result.points[p].enu, o, b.calibration.clock_offset_s), &Ji);
      J.block<2, 3>(static_cast<Eigen::Index>(2 * i), 0) = w * Ji;
      r.segment<2>(static_cast<Eigen::Index>(2 * i)) = w * b.residual_px[seen[i].index];
    }
    if (!ok) continue;
    const Eigen::VectorXd off = r - J * (J.transpose() * J).ldlt().solve(J.transpose() * r);
    for (std::size_t i = 0; i < seen.size(); ++i) {
      const Eigen::Vector2d e = off.segment<2>(static_cast<Eigen::Index>(2 * i));
      series[seen[i].camera].push_back({points[p].time_s, e.x(), e.y()});
    }
  }
  return series;
}

}  // namespace

std::vector<double> image_time_correlation(const NetworkResult& result,
                                           const std::vector<NetworkPoint>& points,
                                           const std::vector<NetworkObservation>& observations) {
  std::vector<double> factor(result.cameras.size(), 1.0);
  std::vector<std::vector<TimedResidual>> series = residuals_off_the_point(result, points, observations);
  for (std::size_t c = 0; c < series.size(); ++c) {
    std::vector<TimedResidual>& r = series[c];
    if (r.size() < kCorrelationMinResiduals) continue;
    std::sort(r.begin(), r.end(), [](const TimedResidual& a, const TimedResidual& b) { return a.t < b.t; });
    const double step = median_step(r);
    if (!(step > 0)) continue;
    const double f = 0.5 * (inflation(r, &TimedResidual::du, step) + inflation(r, &TimedResidual::dv, step));
    const double white_sd = std::sqrt(2.0 * kCorrelationLags / (3.0 * static_cast<double>(r.size())));
    if (f > 1 + kCorrelationFloorSds * white_sd) factor[c] = f;
  }
  return factor;
}

}  // namespace rangecal
