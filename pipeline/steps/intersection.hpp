#pragma once
// The intersection check (docs/intersection.md; seed 002 §4.2 Table 4) as a pure function: calibrated
// cameras and their pole-top picks in, one triangulated point per pole seen by ≥ 2 cameras out,
// compared with the survey where the pole is surveyed, with its predicted 1σ (calibration
// covariance + pick noise, vision/triangulation/triangulation.hpp). File I/O is in
// pipeline/stages/intersect_stage.cpp and pipeline/cli/intersect_command.cpp; choices are in
// docs/intersection.md ("intersect stage").
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "gnss/formats/pole_survey_csv.hpp"
#include "pipeline/io/intersection_csv.hpp"
#include "vision/camera/calibration_result.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

/// One calibrated camera with the pole tops picked in its images.
struct IntersectCamera {
  std::string id;                ///< camera id (names the camera in warnings)
  Camera camera;                 ///< calibrated model
  CameraCovariance calibration;  ///< its parameter covariance (empty = taken as exact)
  std::vector<PolePick> picks;   ///< `id,u,v` picks (docs/formats.md)
};

/// One pole triangulated from ≥ 2 cameras.
struct PoleIntersection {
  std::string id;
  std::vector<std::string> cameras;  ///< ids of the cameras whose picks were used, in camera order
  Eigen::Vector3d enu = Eigen::Vector3d::Zero();     ///< triangulated pole top, site ENU (m)
  double rms_px = 0;                                 ///< reprojection RMS over its views (px)
  double max_ray_angle_deg = 0;                      ///< intersection geometry (largest ray angle)
  Eigen::Matrix3d cov_m2 = Eigen::Matrix3d::Zero();  ///< predicted covariance (m²)
  double sigma_m = 0;                                ///< √trace cov_m2: predicted RMS of ΔR (m)

  bool surveyed = false;  ///< the id is in the survey; the fields below are valid only then
  PoleRole role = PoleRole::check;
  Eigen::Vector3d survey_enu = Eigen::Vector3d::Zero();  ///< surveyed pole top (m)
  Eigen::Vector3d d_enu = Eigen::Vector3d::Zero();       ///< triangulated − surveyed: dE, dN, dU (m)
  double dR = 0;                                         ///< |d_enu| (m), Table 4's ΔR
};

/// Table 4's "mean" row over the surveyed poles of one role, plus the spread a range engineer asks
/// for next. All NaN when n = 0.
struct IntersectionMeans {
  int n = 0;
  Eigen::Vector3d mean_abs_d =
      Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());  ///< mean |dE|, |dN|, |dU| (m)
  double mean_dR = std::numeric_limits<double>::quiet_NaN();                ///< mean ΔR (m)
  double max_dR = std::numeric_limits<double>::quiet_NaN();                 ///< largest ΔR (m)
  double rms_dR = std::numeric_limits<double>::quiet_NaN();  ///< √(mean ΔR²) (m), comparable with sigma_m
  double mean_sigma_m = std::numeric_limits<double>::quiet_NaN();  ///< mean predicted sigma_m (m)
};

struct IntersectionResult {
  /// Surveyed poles in survey order, then unsurveyed ids in order of first appearance.
  std::vector<PoleIntersection> poles;
  IntersectionMeans check;    ///< over `check` poles: the accuracy figure (Table 4 mean row)
  IntersectionMeans control;  ///< over `control` poles (may have been calibration points)
  std::vector<std::string> warnings;
};

/// Triangulates every pole id picked by ≥ 2 cameras (views in camera order, each pick with
/// `pick_sigma_px` per axis) and compares it with `survey` (may be empty: nothing compared, no
/// unknown-id warnings). Never fails for one pole: a pole picked in one camera only, an id not in
/// a non-empty survey (still triangulated, not compared) and a triangulation failure are warnings
/// naming the pole and camera(s); so is a `check` pole picked in no camera. Throws only for bad
/// arguments (pick σ not positive: input error). `cross` (may be null or empty): the covariances
/// between `cameras`' calibrations (block (i, j) over camera i's and j's calibration parameters,
/// e.g. one network's joint covariance, pipeline/io/network_json.hpp); each pole's σ then uses the
/// blocks of the cameras that picked it instead of taking the cameras as independent.
IntersectionResult intersect_poles(const std::vector<IntersectCamera>& cameras,
                                   const std::vector<SurveyedPole>& survey, double pick_sigma_px,
                                   const CrossCovariances* cross = nullptr);

/// The means over the surveyed poles of `role` in `poles`.
IntersectionMeans intersection_means(const std::vector<PoleIntersection>& poles, PoleRole role);

/// The rows of intersection.csv: the surveyed `check` poles of `result`, in its order.
std::vector<IntersectionRow> intersection_rows(const IntersectionResult& result);

/// Table 4's mean row over rows read back (they are all check poles).
IntersectionMeans intersection_means(const std::vector<IntersectionRow>& rows);

}  // namespace rangecal
