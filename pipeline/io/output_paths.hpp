#pragma once
// Every file the stages write under output_dir (docs/outputs.md; docs/outputs.md), named once, with the
// stage that writes it — each file has one writing stage, except run.json, where every stage
// merges its own section (pipeline/io/run_log.hpp). Readers and writers take names from here.
#include <filesystem>
#include <string>

#include "pipeline/mission/mission_config.hpp"

namespace rangecal {

// Mission files, under output_dir.
inline constexpr const char* kLampTrackCsv = "gnss/lamp_track.csv";  ///< gnss stage
inline constexpr const char* kIntersectionCsv = "intersection.csv";  ///< intersect stage
inline constexpr const char* kTrajectoryCsv = "trajectory.csv";      ///< trajectory stage
inline constexpr const char* kTrajectoryJson = "trajectory.json";    ///< trajectory stage
/// calibrate stage, method `network`: its statistics and joint covariance (pipeline/io/network_json.hpp).
inline constexpr const char* kNetworkJson = "network.json";
/// calibrate stage, method `network`: the adjusted lamp track (pipeline/io/lamp_track_adjusted_csv.hpp).
inline constexpr const char* kLampTrackAdjustedCsv = "gnss/lamp_track_adjusted.csv";
inline constexpr const char* kSummaryJson = "summary.json";      ///< report stage
inline constexpr const char* kReportHtml = "report.html";        ///< report stage
inline constexpr const char* kRunJson = "run.json";              ///< every stage, its own section
inline constexpr const char* kMonteCarloCsv = "montecarlo.csv";  ///< `rangecal montecarlo`

// Camera files, under output_dir/<camera id>.
inline constexpr const char* kAlignedCsv = "aligned.csv";                  ///< align stage (our intermediate)
inline constexpr const char* kDetectionsCsv = "detections.csv";            ///< detect stage
inline constexpr const char* kCorrespondencesCsv = "correspondences.csv";  ///< detect stage → calibrate
inline constexpr const char* kCalibrationJson = "calibration.json";        ///< calibrate stage
inline constexpr const char* kCameraOpencvYml = "camera_opencv.yml";       ///< calibrate stage
inline constexpr const char* kDltCoefficientsCsv = "dlt_coefficients.csv";  ///< calibrate stage (DLTdv/Argus)
inline constexpr const char* kArgusProfileTxt = "argus_profile.txt";        ///< calibrate stage (DLTdv/Argus)
inline constexpr const char* kResidualsCsv = "residuals.csv";               ///< calibrate stage
inline constexpr const char* kMethodsCsv = "methods.csv";  ///< calibrate stage, with `compare`
/// calibrate stage, with `compare`: the full result of each compared method.
inline std::string compare_calibration_json(const std::string& method) {
  return "calibration_" + method + ".json";
}

/// `<output_dir>/<file>`.
inline std::string mission_output(const std::string& output_dir, const std::string& file) {
  return (std::filesystem::path(output_dir) / file).string();
}
inline std::string mission_output(const MissionConfig& cfg, const std::string& file) {
  return mission_output(cfg.output_dir, file);
}
/// `<output_dir>/<camera id>/<file>`.
inline std::string camera_output(const std::string& output_dir, const std::string& camera_id,
                                 const std::string& file) {
  return (std::filesystem::path(output_dir) / camera_id / file).string();
}
inline std::string camera_output(const MissionConfig& cfg, const std::string& camera_id,
                                 const std::string& file) {
  return camera_output(cfg.output_dir, camera_id, file);
}
/// `<output_dir>/gnss/lamp_track.csv`.
inline std::string lamp_track_path(const MissionConfig& cfg) {
  return mission_output(cfg, kLampTrackCsv);
}

}  // namespace rangecal
