#pragma once
// One camera's Cramér–Rao bound before flying (docs/accuracy_analysis.md `plan`): from a scenario's
// camera stations and routes alone — no images — the bound of every calibration parameter of each
// camera calibrated on its own.
//
// Observations are the ones the pipeline would get: the simulator's trajectory and frame timing
// (pipeline/simulate/mission_simulator.hpp, noise-free values) give, for every fix GNSS epoch, the nearest
// exported frame within align.max_frame_offset_s in which the lamp is in view — the lamp's true
// ENU position and its exact pixel (and, when the mission calibrates with control poles, those pole
// tops with the survey and pick noise). The noise model is the calibration's: pixel σ (centroid), and
// the PPK σ of the epoch propagated to the pixel, C_i = σ_px²·I + J_X·Σ_X·J_Xᵀ
// (optim/bundle/bundle_adjustment.hpp). At the true parameters θ, with J_i = ∂pixel_i/∂θ
// (vision/triangulation/triangulation.hpp pixel_jacobian_wrt_parameters),
//     F = Σ_i J_iᵀ C_i⁻¹ J_i,   CRB = F⁻¹,
// the smallest covariance any unbiased calibration from these data can reach. No priors enter:
// the bound shows what the geometry alone determines.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "optim/bundle/bundle_observation.hpp"
#include "pipeline/simulate/mission_simulator.hpp"
#include "pipeline/simulate/scenario.hpp"
#include "vision/camera/camera_model.hpp"
#include "vision/camera/camera_parameters.hpp"

namespace rangecal {

/// The default free set and the same with the principal point free.
std::vector<std::vector<std::string>> default_plan_free_sets();

/// The free set the scenario's mission would calibrate (`mission_calibrate.free`), else the default
/// f, k1, pose: what `plan` predicts unless told otherwise. Throws rangecal::Error (config) naming
/// the scenario file and `mission_calibrate.free` when it is not a list of known parameter names.
std::vector<std::string> scenario_free_parameters(const Scenario& s);

struct PlanOptions {
  /// Free-parameter sets to analyse (optim/bundle/bundle_adjustment.hpp names): the default calibration
  /// and the same with the principal point free, to show how well the routes fix it.
  std::vector<std::vector<std::string>> free_sets = default_plan_free_sets();
  double pixel_sigma_px = 0.1;        ///< lamp centroid σ (calibrate_stage.hpp kDefaultPixelSigmaPx)
  double max_frame_offset_s = 0.005;  ///< align.max_frame_offset_s default
  double correlation_limit = 0.99;    ///< |ρ| above this → poorly determined (as the bundle warns)
  /// σ(u0) or σ(v0) above this (px) → poorly determined: a principal point not known to a pixel
  /// shifts every ray by more than the lamp centroids' own noise could explain (docs/optimisation.md).
  double principal_point_limit_px = 1.0;
  /// A clock offset whose σ moves the fastest lamp point by more than this (m) is poorly
  /// determined: the bundle's warning (optim/bundle/bundle_adjustment.cpp), twice one epoch's PPK noise.
  double clock_offset_limit_m = 0.02;
  double rank_tolerance = 1e-14;  ///< relative eigenvalue of the scaled F below which it is singular
  /// Points through the flight volume over which the calibration-only intersection σ of both
  /// methods is predicted (network_vs_per_camera.hpp flight_volume_points), and their fixed seed.
  int volume_points = 400;
  std::uint64_t volume_seed = 77;
  /// Control poles in the "What surveying buys" rows (SurveyBenefit), each capped at the scenario's
  /// number of poles (repeats dropped); empty: not computed.
  std::vector<std::size_t> survey_control_poles = {0, 2, 4};
};

/// The observations camera `camera_index` of the scenario would calibrate from (see above): the
/// lamp points, then — when the scenario's mission_calibrate has use_control_poles: true, as the
/// mission's calibrate stage would — every control pole top inside the image, with the scenario's
/// survey σ per axis and pick σ (the true noise, so the bound is the Cramér–Rao bound).
std::vector<BundleObservation> planned_observations(const Scenario& s, std::size_t camera_index,
                                                    const PlanOptions& options = {});

/// The same from a mission already simulated, for its camera `cam`; `n_lamp` receives how many of
/// them are lamp points (the control poles follow).
std::vector<BundleObservation> mission_observations(const SimMission& m, const SimCamera& cam,
                                                    const PlanOptions& options, std::size_t* n_lamp);

struct ParameterBound {
  CameraParameter parameter = CameraParameter::f;  ///< vision/camera/camera_parameters.hpp; its unit
  double value = 0;                                ///< true value (0 for wx wy wz)
  double sigma = 0;                                ///< √CRB (inf when F is singular)
  double max_abs_correlation = 0;                  ///< with the most correlated other parameter
  std::string correlated_with;
  /// σ / σ-if-every-other-parameter-were-known = 1/√(1 − R²), R the multiple correlation with all
  /// the others (√(F_ii·CRB_ii)): how much the other free parameters cost this one (informative;
  /// with a narrow field of view every pose parameter is inflated tens of times).
  double sigma_inflation = 1;
  /// singular F, |ρ| > correlation_limit, a principal point σ above principal_point_limit_px, or a
  /// clock offset σ × the fastest lamp speed above clock_offset_limit_m
  bool poorly_determined = false;
};

struct CameraBound {
  std::string camera_id;
  int n_points = 0;  ///< observations: lamp points + control poles (when the mission uses them)
  std::vector<CameraParameter> free_parameters;  ///< the rows and columns of `covariance`
  Eigen::MatrixXd covariance;                    ///< the CRB; empty when F is singular
  bool singular = false;
  std::vector<ParameterBound> parameters;
};

/// One observation's terms of F at the truth: J = ∂pixel/∂θ over `params` (the clock offset's column
/// −J_X·v, optim/bundle/bundle_adjustment.hpp), J_X = ∂pixel/∂X, and the effective pixel covariance
/// C = σ_px²·I + J_X·Σ_X·J_Xᵀ (σ_px the observation's own, else `default_pixel_sigma_px`).
struct ObservationTerms {
  Eigen::MatrixXd J;
  Eigen::Matrix<double, 2, 3> Jx = Eigen::Matrix<double, 2, 3>::Zero();
  Eigen::Matrix2d C = Eigen::Matrix2d::Identity();
};
ObservationTerms observation_terms(const Camera& truth, const std::vector<CameraParameter>& params,
                                   const BundleObservation& ob, double default_pixel_sigma_px);

/// Each parameter's σ, strongest correlation and flags from b->covariance (b->singular: all
/// undetermined); `F`, when given, the information the covariance inverts, for the σ inflation;
/// `max_speed` the camera's fastest lamp point (m/s), for the clock offset's rule.
void fill_parameter_bounds(const Camera& truth, const Eigen::MatrixXd* F, double max_speed,
                           const PlanOptions& options, CameraBound* b);

/// The CRB of the parameters named by `free` (expanded like the bundle's) of `truth` from `obs`
/// (pixels are not used: the bound is evaluated at the truth). Throws rangecal::Error
/// (calibration) when a point lies behind the camera.
CameraBound cramer_rao_bound(const Camera& truth, const std::vector<BundleObservation>& obs,
                             const std::vector<std::string>& free, const PlanOptions& options = {});

}  // namespace rangecal
