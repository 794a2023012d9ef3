#pragma once
// The tables `rangecal demo` prints (seed 002 §4 Tables 1–4) with the paper's figures
// beside ours and the simulated truth beside both. Built from the files a finished run wrote
// (calibration*.json, correspondences.csv, pole picks and survey) plus the simulator's truth, so
// what is printed is what a user of `rangecal run` gets.
#include <Eigen/Core>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "pipeline/steps/intersection.hpp"
#include "vision/camera/calibration_result.hpp"

namespace rangecal {

/// One camera of a finished demo run: the calibration by every method that ran, and the truth.
struct DemoCamera {
  std::string id;
  Camera truth;
  std::map<std::string, CalibrationResult> by_method;  ///< "network", "bundle", "tsai", "tsai_sassa", …
  /// Expected RMS reprojection error (px) of a perfect calibration given the simulated noise:
  /// √(mean over used points of the world σ projected to pixels, both axes, + centroid σ²).
  double expected_rms_px = 0;
  /// The network's RMS reprojection error (px) against its own adjusted lamp positions (fix plus
  /// its estimate of the PPK error, gnss/lamp_track_adjusted.csv), over the pairs it used: what its
  /// fit minimised. NaN without a network calibration.
  double network_rms_adjusted_px = std::numeric_limits<double>::quiet_NaN();
};

/// Intersection of the check poles with one method's cameras, against the survey and the truth.
struct DemoIntersection {
  /// One check pole: its error against the truth and the covariance the intersection predicts for
  /// it (calibration and picks; the survey's error is not in a truth comparison).
  struct Pole {
    std::string id;
    Eigen::Vector3d error_m = Eigen::Vector3d::Zero();  ///< triangulated − true pole top, ENU (m)
    Eigen::Matrix3d cov_m2 = Eigen::Matrix3d::Zero();   ///< PoleIntersection::cov_m2
  };
  std::string method;
  IntersectionResult result;      ///< against the survey (Table 4 as the product reports it)
  double mean_dR_truth_m = 0;     ///< mean |triangulated − true pole top| over check poles (m)
  double max_dR_truth_m = 0;      ///< largest of those (m)
  int n_check = 0;                ///< check poles triangulated
  std::vector<Pole> check_poles;  ///< the n_check poles, in survey order
};

/// Errors of a method's parameters against the truth in units of its own reported σ.
struct ParameterCheck {
  std::string name;  ///< f, k1, CE, CN, CU
  double estimate = 0, truth = 0, sigma = 0;
  double z() const { return sigma > 0 ? (estimate - truth) / sigma : 0; }
};
/// f, k1 and the centre of `method`'s calibration (empty when the camera has none).
std::vector<ParameterCheck> parameter_checks(const DemoCamera& cam, const std::string& method);

/// Seed 002 Table 1 layout (u0, v0, f, sx, k1, R, T per method), paper columns first.
std::string format_demo_table1(const DemoCamera& cam);
/// Tables 2–3: reprojection error per method (rms, mean, max) against the PPK fixes, the network's
/// also against its adjusted positions (`rms_adj`), beside the paper's means.
std::string format_demo_tables23(const std::vector<DemoCamera>& cams);
/// Table 4: per check pole dE dN dU dR (cm) of the network and the bundle, and the mean row of every method,
/// beside the paper's means; against the survey and against the truth.
std::string format_demo_table4(const std::vector<DemoIntersection>& by_method);

}  // namespace rangecal
