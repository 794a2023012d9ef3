#include "pipeline/report/lamp_residuals.hpp"

#include <cmath>

#include "optim/bundle/whitening.hpp"
#include "pipeline/steps/calibration_problem.hpp"

namespace rangecal {

std::vector<LampResidual> lamp_residuals(const std::vector<Correspondence>& pairs,
                                         const CalibrationResult* calibration,
                                         const std::vector<ResidualRow>* residuals, double pixel_sigma_px) {
  std::vector<bool> used(pairs.size(), true);
  if (residuals) {
    std::size_t k = 0;
    for (const ResidualRow& row : *residuals)
      if (row.kind == ResidualRow::Kind::lamp && k < used.size()) used[k++] = row.used;
  }
  std::vector<LampResidual> out;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Correspondence& p = pairs[i];
    LampResidual r;
    r.utc = p.utc;
    r.observed = p.uv;
    r.used = used[i];
    if (calibration) {
      const Camera& cam = calibration->camera;
      const Eigen::Vector3d seen =
          p.enu - p.vel_enu.value_or(Eigen::Vector3d::Zero()) * calibration->clock_offset_s;
      r.projected = project(cam, seen, &r.reprojected);
      if (r.projected) {
        r.residual = r.observed - r.reprojected;
        const Eigen::Vector3d sd = p.sd_enu.value_or(Eigen::Vector3d::Constant(kDefaultWorldSigmaM));
        const Eigen::Matrix<double, 2, 3> J = pixel_jacobian_wrt_world(cam, seen);
        const Eigen::Matrix2d C = pixel_sigma_px * pixel_sigma_px * Eigen::Matrix2d::Identity() +
                                  J * sd.cwiseAbs2().asDiagonal() * J.transpose();
        r.sigma_px = C.diagonal().cwiseSqrt();
      }
    }
    out.push_back(r);
  }
  return out;
}

ResidualConsistency residual_consistency(const std::vector<LampResidual>& r, int n_parameters) {
  ResidualConsistency c;
  double ss = 0, expected = 0;
  for (const LampResidual& x : r) {
    if (!x.used || !x.projected) continue;
    ++c.n;
    ss += x.residual.squaredNorm();
    expected += x.sigma_px.squaredNorm();
  }
  if (c.n == 0) return c;
  c.rms_px = std::sqrt(ss / c.n);
  const double dof = std::max(1.0, 2.0 * c.n - n_parameters) / (2.0 * c.n);
  c.expected_rms_px = std::sqrt(expected / c.n * dof);
  return c;
}

}  // namespace rangecal
