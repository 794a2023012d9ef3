// The covariance with the two-scale rank test (optim/estimation/rank_tested_inverse.hpp): the inverse
// of a well-conditioned normal matrix against Eigen's LU inverse; a parameter the data do not touch,
// two parameters in one direction, and a column of rounding noise that Jacobi scaling alone would
// rescue, each reported by name (and by index, RankTestedInverse::named) with no covariance.
#include "optim/estimation/rank_tested_inverse.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

namespace rangecal {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

const std::vector<std::string> kNames = {"f", "k1", "CE", "CN"};

MatrixXd random_jacobian(int rows, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0, 1);
  MatrixXd J(rows, 4);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < 4; ++c) J(r, c) = gauss(rng);
  // Columns of very different scale, as f (mm), k1 (mm⁻²) and the centre (m) have.
  return J * VectorXd((VectorXd(4) << 10.0, 1e4, 3.0, 0.5).finished()).asDiagonal();
}

/// `r` is rank-deficient with no covariance and the one warning `text`, which names the parameters
/// `named` (their indices, as RankTestedInverse::named gives them).
void expect_rank_deficient(const RankTestedInverse& r, const std::string& text,
                           const std::vector<Eigen::Index>& named) {
  EXPECT_TRUE(r.rank_deficient);
  EXPECT_EQ(r.covariance.size(), 0);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0], text);
  EXPECT_EQ(r.named, named);
}

TEST(RankTestedInverse, EqualsTheInverseOfAWellConditionedMatrix) {
  const MatrixXd J = random_jacobian(30, 3);
  const MatrixXd N = J.transpose() * J;
  const RankTestedInverse r = rank_tested_inverse(N, VectorXd::Ones(4), kNames, 1e-14);
  ASSERT_FALSE(r.rank_deficient);
  EXPECT_TRUE(r.warnings.empty());
  const MatrixXd expected = N.fullPivLu().inverse();
  ASSERT_EQ(r.covariance.rows(), 4);
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      EXPECT_NEAR(r.covariance(a, b), expected(a, b), 1e-10 * std::sqrt(expected(a, a) * expected(b, b)))
          << a << ", " << b;
}

TEST(RankTestedInverse, NamesAParameterTheDataDoNotTouch) {
  MatrixXd J = random_jacobian(30, 4);
  J.col(1).setZero();
  expect_rank_deficient(rank_tested_inverse(J.transpose() * J, VectorXd::Ones(4), kNames, 1e-14),
                        "covariance is rank-deficient: the data do not depend on k1 at all (fix it or add "
                        "observations that do)",
                        {1});
}

TEST(RankTestedInverse, NamesTwoParametersInOneDirection) {
  MatrixXd J = random_jacobian(30, 5);
  J.col(3) = -0.25 * J.col(2);  // CN only ever moves with CE
  expect_rank_deficient(rank_tested_inverse(J.transpose() * J, VectorXd::Ones(4), kNames, 1e-14),
                        "covariance is rank-deficient: CE, CN cannot be determined from these data; fix some "
                        "of them or add a prior",
                        {2, 3});
}

TEST(RankTestedInverse, ThePhysicalRangeCatchesAColumnOfRoundingNoise) {
  // k1's column is 1e-12 of the others: over its physical range (1) it moves nothing, though after
  // Jacobi scaling it looks as well determined as the rest.
  MatrixXd J = random_jacobian(30, 6);
  J.col(1) *= 1e-12 / 1e4;
  const MatrixXd N = J.transpose() * J;
  const VectorXd ranges = VectorXd::Ones(4);
  expect_rank_deficient(rank_tested_inverse(N, ranges, kNames, 1e-14),
                        "covariance is rank-deficient: k1 cannot be determined from these data; fix some of "
                        "them or add a prior",
                        {1});
  // With k1's range as small as its column is weak, the same matrix is invertible.
  VectorXd matched = ranges;
  matched[1] = 1e16;
  EXPECT_FALSE(rank_tested_inverse(N, matched, kNames, 1e-14).rank_deficient);
}

TEST(RankTestedInverse, AnEmptyMatrixHasAnEmptyCovariance) {
  const RankTestedInverse r = rank_tested_inverse(MatrixXd(0, 0), VectorXd(0), {}, 1e-14);
  EXPECT_FALSE(r.rank_deficient);
  EXPECT_EQ(r.covariance.size(), 0);
}

}  // namespace
}  // namespace rangecal
