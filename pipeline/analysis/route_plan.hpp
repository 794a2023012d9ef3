#pragma once
// Flight planning before flying (docs/accuracy_analysis.md `plan`; docs/accuracy_analysis.md): from a
// scenario's camera stations and routes alone — no images — the Cramér–Rao bound of every calibration
// parameter and the predicted intersection 1σ at the poles, so a range can choose routes.
//
// Each camera's own bound (camera_bound.hpp: the observations the pipeline would get, F = Σ JᵀC⁻¹J);
// beside this per-camera bound, the network calibration's (network_plan.hpp: every camera and one
// point per epoch adjusted jointly), and for both methods the calibration-only intersection σ
// through the flight volume, the per-camera one with the cross-covariance its cameras share
// through the fixes (network_vs_per_camera.hpp). Tables and HTML: plan_tables.hpp.
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "optim/network/network_options.hpp"  // kDatumFloorImageFactor
#include "pipeline/analysis/camera_bound.hpp"
#include "pipeline/simulate/scenario.hpp"

namespace rangecal {

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
