#pragma once
// <out>/trajectory.json (docs/outputs.md "trajectory.json"): the trajectory stage's summary for a
// machine — the figures report.html's trajectory section shows (pipeline/report/trajectory_summary),
// the settings that made them, each camera's inputs and share, and the stretches with their UTC
// bounds. The instants themselves are in trajectory.csv, which it names.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gnss/geodesy/geodetic_origin.hpp"
#include "pipeline/io/trajectory_csv.hpp"

namespace rangecal {

/// What the stage knows beyond trajectory.csv's rows.
struct TrajectoryJsonContext {
  GeodeticOrigin origin;  ///< the site's ENU origin (WGS84)
  double rate_hz = 0;     ///< output instants per second
  double extrapolation_sigma_px_per_px = 0;
  nlohmann::json smoothing = nlohmann::json::object();  ///< the smoother's model and q (run.json's)
  /// How the labels' σ was set: run.json's `label_sigma` (mode, instants, excluded, iterations)
  nlohmann::json label_sigma = nlohmann::json::object();
  std::size_t instants_tried = 0;  ///< grid instants from the first to the last two-camera instant
  std::size_t single_camera = 0;   ///< of them, seen by one camera only
  bool joint_covariance = false;   ///< the calibrations' cross covariances were used
  nlohmann::json cameras = nlohmann::json::object();  ///< per camera id: its inputs (run.json's counts)
};

/// The JSON document for `rows` (trajectory.csv as written, in time order).
nlohmann::json trajectory_json(const std::vector<TrajectoryRow>& rows, const TrajectoryJsonContext& context);

}  // namespace rangecal
