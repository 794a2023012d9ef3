#include "optim/network/gauss_markov_elimination.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "config/error.hpp"

namespace rangecal {
namespace {

/// The block Cholesky factor of G: L_jj (lower) and L_{j,j−1}.
struct BlockBidiagonal {
  std::vector<Eigen::Matrix3d> diagonal, below;
};

BlockBidiagonal factor(const GaussMarkovSystem& g) {
  const std::size_t n = g.diagonal.size();
  BlockBidiagonal L;
  L.diagonal.resize(n);
  L.below.assign(n, Eigen::Matrix3d::Zero());
  for (std::size_t j = 0; j < n; ++j) {
    Eigen::Matrix3d D = g.diagonal[j];
    if (j > 0) {
      // L_{j,j−1} = G_{j,j−1}·L_{j−1,j−1}⁻ᵀ
      L.below[j] = g.below[j].asDiagonal() * L.diagonal[j - 1].transpose().inverse();
      D -= L.below[j] * L.below[j].transpose();
    }
    const Eigen::LLT<Eigen::Matrix3d> llt(D);
    if (llt.info() != Eigen::Success)
      throw_calibration_error("network", "the PPK error model's normal equations are not positive definite");
    L.diagonal[j] = llt.matrixL();
  }
  return L;
}

}  // namespace

std::vector<Eigen::Matrix3d> eliminate_gauss_markov(GaussMarkovSystem* g, Eigen::MatrixXd* S,
                                                    Eigen::VectorXd* state_rhs, Eigen::VectorXd* camera_rhs,
                                                    double* log_det) {
  const std::size_t n = g->diagonal.size();
  std::vector<Eigen::Matrix3d> inverse_diagonal(n, Eigen::Matrix3d::Zero());
  if (log_det) *log_det = 0;
  if (n == 0) return inverse_diagonal;
  const BlockBidiagonal L = factor(*g);
  if (log_det)
    for (const Eigen::Matrix3d& Ljj : L.diagonal) *log_det += 2 * Ljj.diagonal().array().log().sum();
  Eigen::MatrixXd& Y = g->B;
  const auto rows = [](std::size_t j) { return Eigen::seqN(3 * static_cast<Eigen::Index>(j), 3); };
  // Forward: Y_j = L_jj⁻¹·(B_j − L_{j,j−1}·Y_{j−1}).
  for (std::size_t j = 0; j < n; ++j) {
    if (j > 0) Y(rows(j), Eigen::all).noalias() -= L.below[j] * Y(rows(j - 1), Eigen::all);
    L.diagonal[j].triangularView<Eigen::Lower>().solveInPlace(Y(rows(j), Eigen::all));
    if (state_rhs) {
      auto y = state_rhs->segment<3>(3 * static_cast<Eigen::Index>(j));
      if (j > 0) y -= L.below[j] * state_rhs->segment<3>(3 * static_cast<Eigen::Index>(j - 1));
      L.diagonal[j].triangularView<Eigen::Lower>().solveInPlace(y);
    }
  }
  if (state_rhs && camera_rhs) camera_rhs->noalias() -= Y.transpose() * *state_rhs;
  S->selfadjointView<Eigen::Lower>().rankUpdate(Y.transpose(), -1.0);
  *S = S->selfadjointView<Eigen::Lower>();
  // Backward: Z_j = L_jj⁻ᵀ·(Y_j − L_{j+1,j}ᵀ·Z_{j+1}), and the diagonal blocks of G⁻¹.
  for (std::size_t j = n; j-- > 0;) {
    if (j + 1 < n)
      Y(rows(j), Eigen::all).noalias() -= L.below[j + 1].transpose() * Y(rows(j + 1), Eigen::all);
    L.diagonal[j].transpose().triangularView<Eigen::Upper>().solveInPlace(Y(rows(j), Eigen::all));
    if (state_rhs) {
      auto z = state_rhs->segment<3>(3 * static_cast<Eigen::Index>(j));
      if (j + 1 < n)
        z -= L.below[j + 1].transpose() * state_rhs->segment<3>(3 * static_cast<Eigen::Index>(j + 1));
      L.diagonal[j].transpose().triangularView<Eigen::Upper>().solveInPlace(z);
    }
    const Eigen::Matrix3d Linv = L.diagonal[j].inverse();
    inverse_diagonal[j] = Linv.transpose() * Linv;
    if (j + 1 < n) {
      const Eigen::Matrix3d C = L.below[j + 1] * Linv;
      inverse_diagonal[j] += C.transpose() * inverse_diagonal[j + 1] * C;
    }
  }
  return inverse_diagonal;
}

}  // namespace rangecal
