#include "optim/network/network_gauss_newton.hpp"

#include <cmath>

#include "config/error.hpp"
#include "optim/network/camera_block.hpp"
#include "optim/network/network_covariance.hpp"

namespace rangecal {
NetworkParameterBlocks moved_by_step(const NetworkLayout& l, const NetworkParameterBlocks& blocks,
                                     const NetworkStep& step, double scale) {
  NetworkParameterBlocks out = blocks;
  for (std::size_t c = 0; c < out.cameras.size(); ++c) {
    CameraBlock cb = CameraBlock::pack(l.setups[c], out.cameras[c], l.starts[c]);
    for (int j = 0; j < cb.size; ++j) cb.values[static_cast<std::size_t>(j)] += scale * step.cameras[c][j];
    cb.unpack(&out.cameras[c]);
    out.cameras[c].rebase_rotation(l.starts[c]);
  }
  for (std::size_t k = 0; k < out.points.size(); ++k)
    for (int a = 0; a < 3; ++a) out.points[k][static_cast<std::size_t>(a)] += scale * step.points[k][a];
  for (std::size_t j = 0; j < out.gm.size(); ++j)
    for (int a = 0; a < 3; ++a) out.gm[j][static_cast<std::size_t>(a)] += scale * step.states[j][a];
  return out;
}

int network_gauss_newton(const NetworkLayout& l, NetworkParameterBlocks* blocks, const NetworkSelection& sel,
                         double tolerance, int max_iterations) {
  NetworkStep step;
  double chi2 = network_gauss_newton_step(l, *blocks, sel, &step);
  if (!std::isfinite(chi2)) throw_calibration_error("network", "the χ² at the solve's start is not finite");
  // A step that predicts a fall of χ² within rounding is at the minimum: trying it would form one
  // more step, as costly as a whole iteration, only to find no change.
  const auto at_minimum = [](const NetworkStep& s, double at) {
    return s.predicted_decrease <= kRoundingChi2 * at;
  };
  if (at_minimum(step, chi2)) return 1;
  int iterations = 1;
  for (; iterations < max_iterations; ++iterations) {
    bool accepted = false;
    double scale = 1;
    for (int h = 0; h <= kMaxHalvings && !accepted; ++h, scale *= 0.5) {
      NetworkParameterBlocks trial = moved_by_step(l, *blocks, step, scale);
      NetworkStep next;
      double next_chi2;
      try {
        next_chi2 = network_gauss_newton_step(l, trial, sel, &next);
      } catch (const Error&) {
        continue;  // a point left the image or went behind a camera: a shorter step
      }
      // A whole step that changes χ² only within rounding is at the minimum: halving it would form
      // kMaxHalvings more steps for nothing.
      if (h == 0 && std::abs(next_chi2 - chi2) <= kRoundingChi2 * chi2) return iterations;
      if (!(next_chi2 <= chi2)) continue;
      const bool converged = chi2 - next_chi2 <= tolerance * chi2;
      *blocks = std::move(trial), step = std::move(next), chi2 = next_chi2, accepted = true;
      if (converged) return iterations;
      if (at_minimum(step, chi2)) return iterations + 1;
    }
    if (!accepted) return iterations;  // no step lowers χ²: at the minimum within rounding
  }
  return iterations;
}

}  // namespace rangecal
