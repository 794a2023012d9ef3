#include "pipeline/steps/covariance_under_model.hpp"

#include <algorithm>

#include "optim/bundle/correlated_ppk_covariance.hpp"
#include "optim/estimation/center_covariance.hpp"
#include "optim/estimation/symmetric_part.hpp"
#include "pipeline/io/network_json.hpp"
#include "pipeline/steps/calibration_methods.hpp"

namespace rangecal {

void restate_covariance_under(const PpkErrorModel& model, const CalibrationProblem& problem,
                              CalibrationResult* result) {
  BundleOptions opt = bundle_options(problem);
  opt.ppk_error = model;
  // Only the bundle estimates the clock offset; the others take the stamps as exact
  // (calibration_methods.cpp), so their covariance has no clock row. No free group holds the clock
  // offset (vision/camera/camera_parameters.hpp): its own name is the one to drop.
  if (result->method != "bundle")
    opt.free.erase(std::remove(opt.free.begin(), opt.free.end(), "clock_offset"), opt.free.end());
  const BundleCovariance c = bundle_covariance_under(model, problem.observations, opt, *result);
  result->parameters = c.free;
  result->covariance.resize(0, 0);
  if (!c.rank_deficient)
    result->covariance = symmetric_part(opt.scale_covariance ? c.covariance_scaled : c.covariance_unscaled);
  result->center_covariance_m2 = center_covariance(*result);
  result->details["ppk_error_model"] = ppk_error_model_json(model, c.gauss_markov_states);
  result->details["covariance"] = c.rank_deficient
                                      ? "none: the bundle's system at this solution is rank-deficient"
                                      : "the bundle's at this solution, the sandwich under ppk_error_model "
                                        "(docs/optimisation.md \"σ under correlated PPK errors\")";
  if (c.rank_deficient)
    result->warnings.push_back(result->method +
                               ": the bundle's system at this solution is rank-deficient; no covariance "
                               "under the estimated PPK error model");
}

}  // namespace rangecal
