#pragma once
// Where each stage writes (SPEC §5), so readers and writers agree on one set of names.
#include <filesystem>
#include <string>

#include "config/mission_config.hpp"

namespace rangecal {

/// `<output_dir>/<camera id>/<file>`.
inline std::string camera_output(const MissionConfig& cfg, const std::string& camera_id,
                                 const std::string& file) {
  return (std::filesystem::path(cfg.output_dir) / camera_id / file).string();
}
/// `<output_dir>/<file>`.
inline std::string mission_output(const MissionConfig& cfg, const std::string& file) {
  return (std::filesystem::path(cfg.output_dir) / file).string();
}

inline constexpr const char* kAlignedCsv = "aligned.csv";                  ///< align stage (our intermediate)
inline constexpr const char* kDetectionsCsv = "detections.csv";            ///< detect stage
inline constexpr const char* kCorrespondencesCsv = "correspondences.csv";  ///< detect → calibrate
inline constexpr const char* kCalibrationJson = "calibration.json";        ///< calibrate stage
inline constexpr const char* kCameraOpencvYml = "camera_opencv.yml";       ///< calibrate stage
inline constexpr const char* kMethodsCsv = "methods.csv";  ///< calibrate stage, with `compare`
/// calibrate stage, with `compare`: the full result of each compared method.
inline std::string compare_calibration_json(const std::string& method) {
  return "calibration_" + method + ".json";
}

}  // namespace rangecal
