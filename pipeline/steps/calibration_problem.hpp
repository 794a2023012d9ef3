#pragma once
// One camera's calibration problem (docs/optimisation.md): its lamp pairs (from correspondences.csv) and,
// when calibrate.use_control_poles, the `control` pole tops it picked, as observations with their
// noise; its sensor, priors and free parameters. Every calibration method, the Monte Carlo and the
// demo start from this. Noise defaults where the inputs carry no σ: docs/optimisation.md.
#include <cstdint>
#include <string>
#include <vector>

#include "gnss/formats/pole_survey_csv.hpp"
#include "gnss/track/ppk_error_model.hpp"
#include "optim/bundle/bundle_observation.hpp"
#include "optim/bundle/bundle_options.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/mission/mission_config.hpp"
#include "vision/camera/sensor_geometry.hpp"

namespace rangecal {

/// The lamp centroid's σ without cameras[i].pixel_sigma_px (detector: ≤ 0.05 px RMS on simulated frames).
inline constexpr double kDefaultPixelSigmaPx = PixelSigmaConfig{}.centroid_px;
inline constexpr double kDefaultWorldSigmaM = 0.01;  ///< lamp position σ when correspondences lack sd
/// A pole top picked by hand, without cameras[i].pixel_sigma_px.
inline constexpr double kPolePickSigmaPx = PixelSigmaConfig{}.pick_px;

struct CalibrationProblem {
  std::string camera_id;
  SensorGeometry sensor;
  double nominal_focal_mm = 0;
  /// World points with their covariance and pixels with their σ (lamp track, control poles).
  std::vector<BundleObservation> observations;
  /// Ids of the control poles among the observations: they are the last control_pole_ids.size()
  /// observations, in this order.
  std::vector<std::string> control_pole_ids;
  CameraPriors priors;
  std::vector<std::string> free = default_free_parameters();  ///< calibrate.free names
  double pixel_sigma_px = kDefaultPixelSigmaPx;
  std::uint64_t seed = 1;
  /// The PPK fixes' error model the bundle states its σ under (gnss.error_model; BundleOptions::
  /// ppk_error): white by default. The lamp pairs carry their frame times for it.
  PpkErrorModel ppk_error;
};

/// The control poles of one camera: the survey and the camera's picks (both empty when the
/// mission does not calibrate with control poles).
struct ControlPoleViews {
  std::vector<SurveyedPole> survey;
  std::vector<PolePick> picks;
  std::string survey_file;  ///< for messages
  std::string picks_file;   ///< for messages
};

/// Reads the survey and the camera's picks when calibrate.use_control_poles and both are given.
ControlPoleViews read_control_pole_views(const MissionConfig& cfg, const CameraConfig& camera);

/// The problem of `camera` from its lamp pairs (sd per pair, else kDefaultWorldSigmaM; velocity
/// when present; time_s seconds from the first pair) and its picks of `control` poles
/// (calibrate.control_sigma_m per axis, cameras[i].pixel_sigma_px.pick; check poles never calibrate). Throws
/// rangecal::Error (input) naming the picks file and line for an id that is not in the survey.
CalibrationProblem make_calibration_problem(const CameraConfig& camera, const CalibrateConfig& calibrate,
                                            const std::vector<Correspondence>& pairs,
                                            const ControlPoleViews& poles = {});

/// The options method `bundle` solves `problem` with: its free set, σ_px, PPK error model and the
/// priors on the parameters that are free.
BundleOptions bundle_options(const CalibrationProblem& problem);

}  // namespace rangecal
