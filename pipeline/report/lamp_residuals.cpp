#include "pipeline/report/lamp_residuals.hpp"

#include <algorithm>
#include <cmath>

#include "optim/bundle/whitening.hpp"
#include "pipeline/steps/calibration_problem.hpp"

namespace rangecal {

std::vector<LampResidual> lamp_residuals(const std::vector<Correspondence>& pairs,
                                         const CalibrationResult* calibration,
                                         const std::vector<ResidualRow>* residuals, double pixel_sigma_px,
                                         const PpkErrorModel* ppk_model) {
  const PpkErrorModel white;
  const PpkErrorModel& model = ppk_model ? *ppk_model : white;
  // A model correlated on some axes only is refused where it is read (ppk_error_model.hpp), so the
  // Gauss–Markov variance counts when the model has its part.
  const Eigen::Vector3d gm_var =
      model.correlated() ? model.gm_sd().cwiseAbs2().eval() : Eigen::Vector3d::Zero().eval();
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
        const Eigen::Vector3d var = sd.cwiseProduct(model.white_scale()).cwiseAbs2() + gm_var;
        const Eigen::Matrix2d C = pixel_sigma_px * pixel_sigma_px * Eigen::Matrix2d::Identity() +
                                  J * var.asDiagonal() * J.transpose();
        r.sigma_px = C.diagonal().cwiseSqrt();
        r.cov_px = C;
        r.world_jacobian = J;
        if (p.vel_enu) r.image_velocity_px_s = J * *p.vel_enu;
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

ClockOffsetSignature clock_offset_signature(const std::vector<LampResidual>& r,
                                            const PpkErrorModel* ppk_model) {
  std::vector<const LampResidual*> x;
  for (const LampResidual& e : r)
    if (e.used && e.projected && e.image_velocity_px_s.allFinite()) x.push_back(&e);
  ClockOffsetSignature s;
  s.n = static_cast<int>(x.size());
  double gg = 0, gr = 0, var = 0;
  for (const LampResidual* e : x) {
    const Eigen::Vector2d& g = e->image_velocity_px_s;
    gg += g.squaredNorm();
    gr += g.dot(e->residual);
    var += g.dot(e->cov_px * g);  // C_i holds the Gauss–Markov part's own variance already
  }
  if (!(gg > 0)) return s;
  if (ppk_model && ppk_model->correlated()) {
    // 2·Σ_{i>j} a_iᵀ diag(σ_g²·φ(t_i − t_j)) a_j with a_i = J_iᵀ·g_i: per axis, the running sum
    // F_i = Σ_{j<i} a_j·φ(t_i − t_j) = φ(t_i − t_{i−1})·(F_{i−1} + a_{i−1}).
    std::sort(x.begin(), x.end(),
              [](const LampResidual* a, const LampResidual* b) { return a->utc < b->utc; });
    const Eigen::Vector3d gm_var = ppk_model->gm_sd().cwiseAbs2();
    Eigen::Vector3d f = Eigen::Vector3d::Zero(), a_prev = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < x.size(); ++i) {
      const Eigen::Vector3d a = x[i]->world_jacobian.transpose() * x[i]->image_velocity_px_s;
      if (i > 0) {
        const double dt = 1e-9 * static_cast<double>(x[i]->utc.ns - x[i - 1]->utc.ns);
        f = gauss_markov_transition(*ppk_model, dt).cwiseProduct(f + a_prev);
        var += 2 * a.cwiseProduct(gm_var).dot(f);
      }
      a_prev = a;
    }
  }
  s.offset_s = -gr / gg;
  s.sigma_s = std::sqrt(std::max(0.0, var)) / gg;
  return s;
}

}  // namespace rangecal
