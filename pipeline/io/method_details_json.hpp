#pragma once
// calibration.json's `details` (docs/outputs.md): what each calibration method did, from the
// method's typed result. Keys are sorted (nlohmann::json's order), values deterministic (no wall
// times), so the same run gives the same bytes.
#include <nlohmann/json.hpp>

#include "optim/bundle/bundle_adjustment.hpp"
#include "optim/methods/dlt_lmqn.hpp"
#include "optim/methods/tsai_sassa.hpp"
#include "vision/calibration/tsai.hpp"

namespace rangecal {

/// Tsai: linear f and Tz, where step 2 started (the linear solve, the nominal focal length or the
/// depth profile, with the linear f's relative σ), step 1's rms and frames, step 2's iterations,
/// convergence and any fallback, rms on the sensor.
nlohmann::json tsai_details_json(const TsaiResult& t);

/// SA-sparrow search and LM polish (seeds/SSA.md): θ0 (and where its f, Tz came from), S, the
/// searched parameters, step 1, the
/// search (θ, z, ‖z‖, objective, rms, evaluations, population, iterations, anneal, T0, seed) and the
/// polish (θ, objective, iterations, residual evaluations, converged, distance moved in z).
nlohmann::json tsai_sassa_details_json(const TsaiSassaResult& t, const TsaiSassaOptions& options);

/// DLT and LM-QN: RANSAC inliers, outliers and iterations, DLT rms and dropped skew, final
/// inliers, LM-QN iterations by kind, its stop reason and χ².
nlohmann::json dlt_lmqn_details_json(const DltLmqnResult& r);

/// The bundle: free parameters, solves (`stages`: loss, iterations, rejected), iterations, χ²,
/// dof, variance factor, whether σ are scaled by it, rank deficiency, outlier threshold, pixel σ,
/// the clock offset (when free), σ unscaled and scaled per parameter, the outliers.
nlohmann::json bundle_details_json(const BundleDetails& d);

}  // namespace rangecal
