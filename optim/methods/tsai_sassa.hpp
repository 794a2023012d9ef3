#pragma once
// `tsai_sassa` (docs/optimisation.md; seed 002 §3.2.3): the paper's method — Tsai step 1 (R, Tx, Ty, sx
// linearly, vision/calibration/tsai.hpp), then f, Tz, k1 by simulated-annealing sparrow search (SA-SSA,
// optim/search/sparrow_search.hpp) minimising the eq. 13 residual, finished by a local Levenberg–Marquardt
// polish. As seeds/SSA.md requires, the search runs in normalised coordinates θ = θ0 + S·z around
// the initial estimate θ0 (Tsai's linear f, Tz — or, where that solve is ill-conditioned, the lens's
// nominal f — and k1 = 0), and ‖z‖ of its result is reported so
// the origin bias of SSA (a pull toward θ0) is visible. The result records the search and the
// polish separately (calibration details), so methods.csv shows what the search itself achieved.
//
// Optionally (all_parameters) the search and the polish cover every parameter of the model
// (f, Tz, k1, sx, u0, v0, rotation perturbation wx wy wz, Tx, Ty), minimising the pixel
// reprojection error through vision/camera/camera_model.hpp instead of eq. 13 — seed 002 Table 1 moved
// u0, v0 and sx too.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "optim/bundle/calibration_warning.hpp"
#include "optim/search/lm_qn.hpp"
#include "optim/search/sparrow_search.hpp"
#include "vision/calibration/point_correspondence.hpp"
#include "vision/calibration/tsai.hpp"
#include "vision/camera/calibration_result.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal {

struct TsaiSassaOptions {
  SparrowOptions search = [] {
    SparrowOptions o;  // SA-SSA, CI-sized defaults (SSA.md); the paper's size is n = 100, M = 1000
    o.anneal = true;
    o.population = 30;
    o.max_iterations = 200;
    o.seed = 20220101;
    return o;
  }();
  bool all_parameters = false;
  /// The lens's nominal focal length (mm; ≤ 0: unknown). Where Tsai's linear f, Tz solve is
  /// ill-conditioned (the f–distance ridge of a narrow field) the search starts from it
  /// (tsai_f_tz_start, vision/calibration/tsai.hpp).
  double nominal_f_mm = 0;
  /// Half-ranges S (same order as the searched parameters); empty → defaults:
  /// f ±20 % of f0, Tz ±20 % of the mean point depth Zc (Tz itself can be ~0 when the world origin
  /// is near the camera), k1 ±0.05/r_max² (5 % distortion at the image corner),
  /// and with all_parameters: sx ±0.02, u0 v0 ±20 px, w ±5 mrad, Tx Ty ±2 % of ‖T0‖ (≥ 0.5 units).
  Eigen::VectorXd half_range;
  bool polish = true;  ///< finish with plain LM from the search result
  LmQnOptions polish_options = [] {
    LmQnOptions o;
    o.allow_qn = false;
    return o;
  }();
};

struct TsaiSassaResult {
  TsaiStep1 step1;
  TsaiStart start;  ///< how θ0's f, Tz were found (tsai_sassa_calibrate; default for tsai_sassa_from)
  std::vector<CameraParameter> parameters;  ///< searched parameters, order of theta0/half_range
  Eigen::VectorXd theta0;                   ///< initial estimate (Tsai's linear f, Tz; k1 = 0; step 1 values)
  Eigen::VectorXd half_range;               ///< S
  NormalisedSearchResult search;            ///< SA-SSA result: θ, z, ‖z‖, evaluations
  double search_rms_px = 0;                 ///< RMS reprojection error of the searched camera
  Camera camera_search;                     ///< camera from the search alone
  bool polished = false;
  LmQnResult polish;  ///< LM polish (in z coordinates) from the search result
  Eigen::VectorXd theta_polished;
  Camera camera;  ///< final camera (polished if polish is on)
  /// Method "tsai_sassa": camera, reprojection over all points, warnings (a search that ended at
  /// the edge of its range, a polish that did not converge). The search and polish figures are in
  /// the fields above (pipeline I/O writes them into calibration.json's details).
  CalibrationResult calibration;
  /// calibration.warnings typed (optim/bundle/calibration_warning.hpp): the same, in the same order.
  std::vector<CalibrationWarning> warnings;
};

/// The whole method from correspondences. Throws rangecal::Error (calibration) on degenerate
/// input (from Tsai step 1) or inconsistent options.
TsaiSassaResult tsai_sassa_calibrate(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                                     const TsaiSassaOptions& options = {});

/// The search and polish from a given step 1 and start θ0 (f, Tz, k1, then the optional extra
/// parameters); for tests and comparisons that start deliberately off the truth.
TsaiSassaResult tsai_sassa_from(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                                const TsaiStep1& step1, const Eigen::VectorXd& theta0,
                                const TsaiSassaOptions& options = {});

/// Default half-ranges S for θ0 (see TsaiSassaOptions::half_range).
Eigen::VectorXd tsai_sassa_default_half_range(const std::vector<PointCorrespondence>& pts,
                                              const TsaiSensor& sensor, const TsaiStep1& step1,
                                              const Eigen::VectorXd& theta0);

/// The objective the search minimises at θ: Σ eq. 13 residual² (sensor mm²) for (f, Tz, k1), or
/// Σ pixel reprojection error² (px²) with all parameters. +∞ where the camera cannot project.
double tsai_sassa_objective(const std::vector<PointCorrespondence>& pts, const TsaiSensor& sensor,
                            const TsaiStep1& step1, const Eigen::VectorXd& theta);

/// The camera at θ (same parameterisation).
Camera tsai_sassa_camera(const TsaiSensor& sensor, const TsaiStep1& step1, const Eigen::VectorXd& theta);

}  // namespace rangecal
