#pragma once
// The covariance of a normal matrix with the two-scale rank test the per-camera bundle and the
// network share (docs/optimisation.md "Covariance"). Before N = JᵀJ is inverted:
//   - a parameter whose diagonal is not positive is not in the data at all;
//   - the smallest eigenvalue of N with columns scaled by each parameter's full physical range
//     (parameter_range, vision/camera/camera_parameters.hpp) — so a column that is only rounding
//     noise is not rescued by Jacobi scaling — or of the Jacobi-scaled N is below
//     rank_tolerance × the largest: the parameters with a share above 0.2 in that eigenvector
//     cannot be determined from these data.
// Either way the covariance is left empty and a warning names the parameters. Otherwise
// Σ = D·(D·N·D)⁻¹·D with D = diag(1/√N_jj), inverted over the eigenvalues of the scaled matrix.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace rangecal {

struct RankTestedInverse {
  Eigen::MatrixXd covariance;  ///< N⁻¹; empty when rank-deficient (or N is 0 × 0)
  bool rank_deficient = false;
  std::vector<std::string> warnings;  ///< the rank-deficiency message, naming the parameters
  std::vector<Eigen::Index> named;    ///< the parameters that message names (N's order)
};

/// N⁻¹ of the symmetric normal matrix `N` with the rank tests above. `physical_range` holds each
/// parameter's range (N's order) and `names` its name for the warnings.
RankTestedInverse rank_tested_inverse(const Eigen::MatrixXd& N, const Eigen::VectorXd& physical_range,
                                      const std::vector<std::string>& names, double rank_tolerance);

}  // namespace rangecal
