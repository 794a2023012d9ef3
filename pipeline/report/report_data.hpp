#pragma once
// What the report stage (SPEC §4.6) shows, read only from the files the earlier stages wrote in the
// output folder, so `rangecal report CONFIG` runs alone. Any per-camera file may be missing (a
// camera that failed calibration, a run without `compare`, no intersect stage yet): the data says
// what is missing instead of failing. A file that is present but malformed is an input error naming
// the file, line and field (the readers of each format do that).
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "gnss/time/utc_time.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/intersection_csv.hpp"
#include "vision/camera/calibration_result.hpp"

namespace rangecal {

/// `gnss/lamp_track.csv` in brief (the mission section).
struct LampTrackSummary {
  std::size_t epochs = 0;
  UtcTime start, end;
};

/// One row of `<cam>/methods.csv` (pipeline/stages/calibrate_stage.cpp format_methods_csv; seed 002
/// Table 1 layout).
struct MethodRow {
  std::string method;
  double u0_px = 0, v0_px = 0, f_mm = 0, sx = 1, k1_per_mm2 = 0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d T = Eigen::Vector3d::Zero();
  std::optional<double> sigma_f_mm;
  double rms_px = 0;
  int n_used = 0;
  int n_rejected = 0;
};

/// Everything the report knows about one camera of the config.
struct CameraReportData {
  std::string id;
  std::optional<CalibrationResult> calibration;      ///< absent: calibration.json missing
  std::optional<std::vector<Correspondence>> pairs;  ///< absent: correspondences.csv missing
  std::optional<std::vector<MethodRow>> methods;     ///< absent: methods.csv missing (no `compare`)
  /// run.json calibrate counts "<cam>.failed": why the calibrate stage gave up on the camera.
  std::string calibration_failure;
  /// Image size (px) for the plots: calibration.json's, else 0 until the caller sets the config's.
  int width_px = 0;
  int height_px = 0;
};

/// Warnings of one stage, from run.json (`stages.<name>.warnings`).
struct StageWarnings {
  std::string stage;
  std::vector<std::string> warnings;
};

struct ReportData {
  std::string mission;                    ///< the config's free text
  std::string program_version;            ///< from run.json; empty when run.json is missing
  std::string config_sha256;              ///< from run.json; empty when run.json is missing
  std::optional<LampTrackSummary> track;  ///< absent: gnss/lamp_track.csv missing
  std::vector<CameraReportData> cameras;  ///< in config order
  /// intersection.csv as the intersect stage wrote it (pipeline/io/intersection_csv.hpp); absent:
  /// the file is missing.
  std::optional<std::vector<IntersectionRow>> intersection;
  std::vector<StageWarnings> stage_warnings;  ///< stages in run.json order (sorted by name)
};

/// Parses methods.csv text (`path` for messages); errors name file, line and column.
std::vector<MethodRow> parse_methods_csv(const std::string& text, const std::string& path);

/// Reads `output_dir` for the given cameras. Missing files are recorded as absent; malformed files
/// throw rangecal::Error (kind input) naming file, line and field.
ReportData read_report_data(const std::string& output_dir, const std::string& mission,
                            const std::vector<std::string>& camera_ids);

}  // namespace rangecal
