#include "optim/network/gauss_markov_elimination.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <utility>

#include "config/error.hpp"

namespace rangecal {

GaussMarkovFactor factor_gauss_markov(const GaussMarkovSystem& g) {
  const std::size_t n = g.diagonal.size();
  GaussMarkovFactor L;
  L.diagonal.resize(n), L.diagonal_inverse.resize(n);
  L.below.assign(n, Eigen::Matrix3d::Zero());
  for (std::size_t j = 0; j < n; ++j) {
    Eigen::Matrix3d D = g.diagonal[j];
    if (j > 0) {
      // L_{j,j−1} = G_{j,j−1}·L_{j−1,j−1}⁻ᵀ
      L.below[j] = g.below[j].asDiagonal() * L.diagonal_inverse[j - 1].transpose();
      D -= L.below[j] * L.below[j].transpose();
    }
    const Eigen::LLT<Eigen::Matrix3d> llt(D);
    if (llt.info() != Eigen::Success)
      throw_calibration_error("network", "the PPK error model's normal equations are not positive definite");
    L.diagonal[j] = llt.matrixL();
    L.diagonal_inverse[j] = L.diagonal[j].inverse();
  }
  return L;
}

void solve_gauss_markov(const GaussMarkovFactor& L, Eigen::MatrixXd* rhs) {
  const std::size_t n = L.diagonal.size();
  const auto at = [&](std::size_t j) { return rhs->middleRows<3>(3 * static_cast<Eigen::Index>(j)); };
  Eigen::Matrix<double, 3, Eigen::Dynamic> t(3, rhs->cols());
  for (std::size_t j = 0; j < n; ++j) {
    t = at(j);
    if (j > 0) t.noalias() -= L.below[j] * at(j - 1);
    at(j).noalias() = L.diagonal_inverse[j] * t;
  }
  for (std::size_t j = n; j-- > 0;) {
    t = at(j);
    if (j + 1 < n) t.noalias() -= L.below[j + 1].transpose() * at(j + 1);
    at(j).noalias() = L.diagonal_inverse[j].transpose() * t;
  }
}

std::vector<Eigen::Matrix3d> gauss_markov_inverse_below(
    const GaussMarkovFactor& L, const std::vector<Eigen::Matrix3d>& inverse_diagonal) {
  std::vector<Eigen::Matrix3d> below(L.diagonal.size(), Eigen::Matrix3d::Zero());
  for (std::size_t j = 1; j < below.size(); ++j)
    below[j] = -inverse_diagonal[j] * L.below[j] * L.diagonal_inverse[j - 1];
  return below;
}

std::vector<Eigen::Matrix3d> eliminate_gauss_markov(GaussMarkovSystem* g, Eigen::MatrixXd* S,
                                                    Eigen::VectorXd* state_rhs, Eigen::VectorXd* camera_rhs,
                                                    double* log_det, GaussMarkovFactor* factor_out) {
  const std::size_t n = g->diagonal.size();
  std::vector<Eigen::Matrix3d> inverse_diagonal(n, Eigen::Matrix3d::Zero());
  if (log_det) *log_det = 0;
  if (n == 0) return inverse_diagonal;
  GaussMarkovFactor L = factor_gauss_markov(*g);
  if (log_det)
    for (const Eigen::Matrix3d& Ljj : L.diagonal) *log_det += 2 * Ljj.diagonal().array().log().sum();
  Eigen::MatrixXd& Y = g->B;
  const auto rows = [](std::size_t j) { return Eigen::seqN(3 * static_cast<Eigen::Index>(j), 3); };
  // Forward: Y_j = L_jj⁻¹·(B_j − L_{j,j−1}·Y_{j−1}), by the factor's 3×3 inverses.
  const std::vector<Eigen::Matrix3d>& Linv = L.diagonal_inverse;
  Eigen::Matrix<double, 3, Eigen::Dynamic> t(3, Y.cols());
  for (std::size_t j = 0; j < n; ++j) {
    t = Y(rows(j), Eigen::all);
    if (j > 0) t.noalias() -= L.below[j] * Y(rows(j - 1), Eigen::all);
    Y(rows(j), Eigen::all).noalias() = Linv[j] * t;
    if (state_rhs) {
      auto y = state_rhs->segment<3>(3 * static_cast<Eigen::Index>(j));
      if (j > 0) y -= L.below[j] * state_rhs->segment<3>(3 * static_cast<Eigen::Index>(j - 1));
      y = Linv[j] * y;
    }
  }
  if (state_rhs && camera_rhs) camera_rhs->noalias() -= Y.transpose() * *state_rhs;
  S->selfadjointView<Eigen::Lower>().rankUpdate(Y.transpose(), -1.0);
  *S = S->selfadjointView<Eigen::Lower>();
  // Backward: Z_j = L_jj⁻ᵀ·(Y_j − L_{j+1,j}ᵀ·Z_{j+1}), and the diagonal blocks of G⁻¹.
  for (std::size_t j = n; j-- > 0;) {
    t = Y(rows(j), Eigen::all);
    if (j + 1 < n) t.noalias() -= L.below[j + 1].transpose() * Y(rows(j + 1), Eigen::all);
    Y(rows(j), Eigen::all).noalias() = Linv[j].transpose() * t;
    if (state_rhs) {
      auto z = state_rhs->segment<3>(3 * static_cast<Eigen::Index>(j));
      if (j + 1 < n)
        z -= L.below[j + 1].transpose() * state_rhs->segment<3>(3 * static_cast<Eigen::Index>(j + 1));
      z = Linv[j].transpose() * z;
    }
    inverse_diagonal[j] = Linv[j].transpose() * Linv[j];
    if (j + 1 < n) {
      const Eigen::Matrix3d C = L.below[j + 1] * Linv[j];
      inverse_diagonal[j] += C.transpose() * inverse_diagonal[j + 1] * C;
    }
  }
  if (factor_out) *factor_out = std::move(L);  // kept, not copied: the likelihood factors every evaluation
  return inverse_diagonal;
}

}  // namespace rangecal
