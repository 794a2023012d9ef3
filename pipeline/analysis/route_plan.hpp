#pragma once
// Flight planning before flying (docs/accuracy_analysis.md `plan`; docs/accuracy_analysis.md): from a
// scenario's camera stations and routes alone — no images — the Cramér–Rao bound of every calibration
// parameter and the predicted intersection 1σ at the poles, so a range can choose routes.
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
//
// Beside this per-camera bound, the network calibration's (network_plan.hpp: every camera and one
// point per epoch adjusted jointly), and for both methods the calibration-only intersection σ
// through the flight volume, the per-camera one with the cross-covariance its cameras share
// through the fixes (network_vs_per_camera.hpp). Tables and HTML: plan_tables.hpp.
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "optim/bundle/bundle_adjustment.hpp"
#include "optim/network/network_options.hpp"  // kDatumFloorImageFactor
#include "pipeline/simulate/scenario.hpp"

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

/// The CRB of the parameters named by `free` (expanded like the bundle's) of `truth` from `obs`
/// (pixels are not used: the bound is evaluated at the truth). Throws rangecal::Error
/// (calibration) when a point lies behind the camera.
CameraBound cramer_rao_bound(const Camera& truth, const std::vector<BundleObservation>& obs,
                             const std::vector<std::string>& free, const PlanOptions& options = {});

struct PoleBound {
  std::string id;
  std::string role;
  int n_cameras = 0;  ///< cameras whose image holds it
  /// Predicted √trace Σ_X (m) under the calibration the run would make (the network's joint bound
  /// with its cross blocks when the cameras share epochs, else the per-camera joint covariance).
  double sigma_m = std::numeric_limits<double>::quiet_NaN();
  /// The same from each camera's own bound, the cameras taken as independent: what separate
  /// per-camera calibration.json files would state (m).
  double per_camera_independent_sigma_m = std::numeric_limits<double>::quiet_NaN();
};

/// The network calibration's bound beside the per-camera one (docs/accuracy_analysis.md "Network
/// beside per-camera"): the Cramér–Rao bound of the joint adjustment of every camera and one point
/// per lamp epoch (network_plan.hpp network_cramer_rao_bound), split into cameras.
struct NetworkBound {
  /// Lamp epochs seen by ≥ 2 cameras. Only with some does `rangecal run` calibrate as a network
  /// (its default then); otherwise the network is the per-camera calibration (`cameras` equal it).
  int shared_epochs = 0;
  bool applies() const { return shared_epochs > 0; }
  bool singular = false;  ///< the reduced camera system is rank-deficient (σ undetermined)
  Eigen::MatrixXd joint;  ///< all cameras' free parameters, cameras in order; empty when singular
  /// Per camera its diagonal block: σ, correlation and flags as the per-camera bound's (no σ
  /// inflation: NaN); n_points as the per-camera bound's.
  std::vector<CameraBound> cameras;
};

/// Calibration-only intersection 1σ through the flight volume (m): the rms over the points of
/// √trace Σ_cal of a point triangulated from noise-free pixels (network_vs_per_camera.hpp).
struct VolumeIntersection {
  int n_points = 0;  ///< points inside ≥ 2 images (0 with one camera)
  /// The per-camera calibrations with their shared-fix cross-covariances: the honest prediction.
  double per_camera_m = std::numeric_limits<double>::quiet_NaN();
  /// The same with the cameras taken as independent (cross blocks dropped): what the separate
  /// calibration.json files alone would predict.
  double per_camera_independent_m = std::numeric_limits<double>::quiet_NaN();
  double network_m = std::numeric_limits<double>::quiet_NaN();  ///< the network's joint covariance
  double network_independent_m = std::numeric_limits<double>::quiet_NaN();  ///< its cross blocks dropped
  /// The network with every centroid and pick σ divided by kDatumFloorImageFactor: what the PPK
  /// fixes and the control survey alone allow, a floor no image quality lowers
  /// (docs/accuracy_analysis.md "Datum floor").
  double network_datum_floor_m = std::numeric_limits<double>::quiet_NaN();
};

/// σ per axis of a surveyed camera station in `plan`'s "What surveying buys" table (m).
inline constexpr double kSurveyedStationSigmaM = 0.005;

/// What surveying would buy (docs/accuracy_analysis.md "What surveying buys"): the network's
/// calibration-only intersection 1σ through the flight volume (m, as VolumeIntersection::network_m)
/// with `control_poles[i]` of the scenario's poles as control (network_plan.hpp with_survey) and the
/// camera stations free (`stations_free_m[i]`) or surveyed to kSurveyedStationSigmaM
/// (`stations_surveyed_m[i]`). Empty when not computed.
struct SurveyBenefit {
  std::vector<std::size_t> control_poles;
  std::vector<double> stations_free_m, stations_surveyed_m;
};

struct FreeSetPlan {
  std::vector<std::string> free;
  std::vector<CameraBound> cameras;
  std::vector<PoleBound> poles;
  NetworkBound network;
  VolumeIntersection volume;
  SurveyBenefit survey;  ///< for the first free set only (each row costs two network bounds)
};

/// One candidate (a scenario) analysed for every free set.
struct RoutePlanAnalysis {
  std::string name;
  std::vector<FreeSetPlan> free_sets;
};

/// Analyses scenario `s` under `name`. Throws rangecal::Error (calibration) when a camera sees
/// fewer than 6 lamp points.
RoutePlanAnalysis analyse_route_plan(const Scenario& s, const std::string& name,
                                     const PlanOptions& options = {});

}  // namespace rangecal
