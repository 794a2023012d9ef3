#include "optim/estimation/rank_tested_inverse.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace rangecal {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

/// The parameters k with selected(k), in order.
template <typename Selected>
std::vector<Eigen::Index> select(Eigen::Index p, Selected selected) {
  std::vector<Eigen::Index> out;
  for (Eigen::Index k = 0; k < p; ++k)
    if (selected(k)) out.push_back(k);
  return out;
}

/// The names of `which`, comma-separated.
std::string name_list(const std::vector<std::string>& names, const std::vector<Eigen::Index>& which) {
  std::string list;
  for (Eigen::Index k : which) list += (list.empty() ? "" : ", ") + names[static_cast<std::size_t>(k)];
  return list;
}

}  // namespace

RankTestedInverse rank_tested_inverse(const MatrixXd& N, const VectorXd& physical_range,
                                      const std::vector<std::string>& names, double rank_tolerance) {
  RankTestedInverse out;
  const Eigen::Index p = N.rows();
  VectorXd jacobi(p);
  for (Eigen::Index k = 0; k < p; ++k) jacobi[k] = N(k, k) > 0 ? 1 / std::sqrt(N(k, k)) : 0;
  out.named = select(p, [&](Eigen::Index k) { return !(N(k, k) > 0); });
  if (!out.named.empty()) {
    out.rank_deficient = true;
    out.warnings.push_back("covariance is rank-deficient: the data do not depend on " +
                           name_list(names, out.named) + " at all (fix it or add observations that do)");
    return out;
  }
  if (p == 0) return out;
  const Eigen::SelfAdjointEigenSolver<MatrixXd> physical(physical_range.asDiagonal() * N *
                                                         physical_range.asDiagonal());
  const Eigen::SelfAdjointEigenSolver<MatrixXd> scaled(jacobi.asDiagonal() * N * jacobi.asDiagonal());
  const VectorXd lt = physical.eigenvalues(), lam = scaled.eigenvalues();
  const bool physical_ok = lt[0] > rank_tolerance * lt[p - 1];
  if (!physical_ok || !(lam[0] > rank_tolerance * lam[p - 1])) {
    out.rank_deficient = true;
    const VectorXd nullv =
        !physical_ok ? VectorXd(physical.eigenvectors().col(0)) : VectorXd(scaled.eigenvectors().col(0));
    out.named = select(p, [&](Eigen::Index k) { return std::abs(nullv[k]) > 0.2; });
    out.warnings.push_back("covariance is rank-deficient: " + name_list(names, out.named) +
                           " cannot be determined from these data; fix some of them or add a prior");
    return out;
  }
  const MatrixXd inverse =
      scaled.eigenvectors() * lam.cwiseInverse().asDiagonal() * scaled.eigenvectors().transpose();
  out.covariance = jacobi.asDiagonal() * inverse * jacobi.asDiagonal();
  return out;
}

}  // namespace rangecal
