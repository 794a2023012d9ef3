#pragma once
// A moving target's trajectory from calibrated cameras' 2-D tracks (docs/trajectory.md): at each
// output instant t, every camera that labelled the target in the two frames around t gives one view —
// its label linearly interpolated to t, with the image velocity between those frames — and the views
// are triangulated (triangulation.hpp) with the point's covariance from three sources:
//   labels:       the camera's label σ per axis (the network's estimated image variance component, a
//                 stated σ, a label's own), taken whole for the interpolated label (neighbouring
//                 labels' errors are correlated on real tracks, so no √((1−a)² + a²) reduction is
//                 claimed) — or, when asked, estimated from the views' disagreement with that σ as
//                 its a-priori value and the labels' correlation with it
//                 (label_variance_components.hpp);
//   timing:       the label's instant is uncertain by σ_t (the camera clock's σ at that time, its
//                 wander, a stated timing σ), which moves it by σ_t·g along its image velocity g;
//   calibration:  each camera's parameter covariance and, for cameras calibrated together, the cross
//                 blocks of the joint covariance.
// When the views disagree beyond those σ (the instant's χ² test), the covariance is scaled by the
// instant's a-posteriori variance factor (TrajectoryPoint::inflated).
// Velocity by central difference of the neighbouring instants' positions, its σ from their label and
// timing parts only: the calibration's error is common to neighbouring instants and cancels in the
// difference to first order.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"
#include "vision/calibration/image_coverage.hpp"
#include "vision/triangulation/label_variance_components.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

/// One label of the target, at its own instant.
struct TimedLabel {
  UtcTime t;                                        ///< the label's true time (clock applied), UTC
  Eigen::Vector2d uv_px = Eigen::Vector2d::Zero();  ///< px, docs/conventions.md
  double timing_sigma_s = 0;                        ///< 1σ of t (s)
  double sigma_px =
      0;          ///< the label's own 1σ per axis (px, the track file's); 0: the camera's label_sigma_px
  long line = 0;  ///< its line in the track file, for messages
};

/// One calibrated camera and its track of the target.
struct TrajectoryCamera {
  std::string id;
  Camera camera;
  CameraCovariance calibration;    ///< empty: taken as exact
  double label_sigma_px = 1;       ///< a label's 1σ per axis (px, > 0) where it gives none of its own
  std::vector<TimedLabel> labels;  ///< strictly increasing t
  ImageCoverage coverage;          ///< where its calibration saw the lamp (empty: unknown)
  /// A calibration's error at the pixel that no parameter of `calibration` carries (an imported
  /// calibration's stated lens residual and its conversion's fit; px per axis, ≥ 0): added to every
  /// view's σ in quadrature (vision/triangulation/stated_calibration_sigma.hpp).
  double model_sigma_px = 0;
};

struct TrajectoryOptions {
  /// Two labels bracket an instant only when they are at most this many of the camera's median frame
  /// intervals apart: a longer gap is a stretch where the target was not seen.
  double max_gap_frames = 2.5;
  /// A view whose label lies d px outside its camera's coverage (ImageCoverage::distance_outside_px)
  /// adds a lens-model error of this × d px per axis to its label σ, in quadrature: a model fitted
  /// where the calibration saw the lamp is extrapolated there, by an error its covariance does not
  /// carry (docs/trajectory.md "Extrapolated views"; 0: none).
  double extrapolation_sigma_px_per_px = 0.05;
  /// Each camera's label σ estimated from the views' disagreement (label_variance_components.hpp;
  /// docs/trajectory.md "Label σ"), the σ given (`label_sigma_px`, a label's own) as its a-priori
  /// value; false (the default): the σ given, as given.
  bool estimate_label_sigma = false;
  /// The estimate uses at most this many instants seen by two cameras or more, evenly spread.
  std::size_t label_sigma_max_instants = 2000;
  LabelVcOptions label_sigma;
};

/// The target at one instant.
struct TrajectoryPoint {
  UtcTime t;
  std::vector<std::string> cameras;  ///< the cameras whose labels were used
  /// Those of them whose label lies outside their calibration's coverage: the point rests there on an
  /// extrapolated lens model, and its σ may not hold.
  std::vector<std::string> extrapolated;
  TriangulationResult fix;  ///< point, covariance (label, timing, calibration parts), residuals
  /// The views' χ² = Σ rᵢᵀ·Cᵢ⁻¹·rᵢ, Cᵢ the label's and timing covariance plus the camera's calibration
  /// covariance projected to its pixel, and its degrees of freedom 2·views − 3.
  double chi2 = 0;
  int dof = 0;
  /// The views disagree beyond their σ (χ² above its 99 % quantile: a label off, or a camera's model
  /// extrapolated where its calibration did not reach): every part of the covariance is then scaled by
  /// χ²/dof, the a-posteriori variance factor of the instant, so that its σ still covers the misfit.
  bool inflated = false;
  Eigen::Vector3d velocity = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());  ///< m/s
  Eigen::Vector3d velocity_sd =
      Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());  ///< m/s; NaN: no neighbours
  /// m/s² and its 1σ: from the smoother's state (vision/triangulation/trajectory_smoother.hpp); NaN
  /// without it.
  Eigen::Vector3d acceleration = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Vector3d acceleration_sd = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
};

struct Trajectory {
  std::vector<TrajectoryPoint> points;  ///< in time order, instants with ≥ 2 cameras only
  std::size_t instants = 0;             ///< instants tried
  std::size_t single_camera = 0;        ///< instants with one camera's view only (not triangulated)
  std::vector<std::string> warnings;    ///< triangulation failures, one per instant (capped)
  /// The labels' σ as estimated (TrajectoryOptions::estimate_label_sigma): per camera its scale of
  /// the σ given, by camera index; empty when not estimated.
  LabelVcResult label_sigma;
  bool label_sigma_estimated = false;
};

/// The instants every 1/rate_hz s on a grid of whole UTC seconds, from the first to the last instant
/// where two or more cameras have labels (rate_hz > 0).
std::vector<UtcTime> trajectory_instants(const std::vector<TrajectoryCamera>& cameras, double rate_hz);

/// The median step between consecutive points (s; the upper median for an even count): the output
/// grid's, against which gaps are judged. 0 for fewer than two points.
double median_step_s(const std::vector<TrajectoryPoint>& points);

/// The median frame rate of the fastest camera's labels (frames/s); 0 when no camera has two labels.
double fastest_label_rate_hz(const std::vector<TrajectoryCamera>& cameras);

/// The trajectory at `instants` (method in the header comment). `cross`: the calibrations' cross
/// covariances by camera index (may be null). Throws rangecal::Error (input) for a label σ not
/// positive or labels not in time order, naming the camera.
Trajectory estimate_trajectory(const std::vector<TrajectoryCamera>& cameras,
                               const std::vector<UtcTime>& instants, const CrossCovariances* cross,
                               const TrajectoryOptions& options = {});

}  // namespace rangecal
