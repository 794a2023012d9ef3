#pragma once
// Hartley normalisation (Hartley & Zisserman §4.4.4): the similarity that moves the points' centroid to
// the origin and their mean distance from it to √D, applied before a DLT or a homography fit so the
// linear system is well conditioned; the fit is then de-normalised with the inverse.
#include <Eigen/Core>
#include <cmath>
#include <vector>

namespace rangecal {

/// The (D+1)×(D+1) homogeneous similarity T for the D-dimensional points `x` (any unit); identity
/// scale when every point is the same.
template <int D>
Eigen::Matrix<double, D + 1, D + 1> hartley_normalisation(const std::vector<Eigen::Matrix<double, D, 1>>& x) {
  Eigen::Matrix<double, D, 1> c = Eigen::Matrix<double, D, 1>::Zero();
  for (const auto& p : x) c += p;
  c /= static_cast<double>(x.size());
  double mean_dist = 0;
  for (const auto& p : x) mean_dist += (p - c).norm();
  mean_dist /= static_cast<double>(x.size());
  const double s = mean_dist > 0 ? std::sqrt(double(D)) / mean_dist : 1.0;
  Eigen::Matrix<double, D + 1, D + 1> T = Eigen::Matrix<double, D + 1, D + 1>::Identity();
  T.template topLeftCorner<D, D>() *= s;
  T.template topRightCorner<D, 1>() = -s * c;
  return T;
}

}  // namespace rangecal
