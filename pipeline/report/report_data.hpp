#pragma once
// What the report stage (docs/outputs.md) shows, read only from the files the earlier stages wrote in the
// output folder, so `rangecal report CONFIG` runs alone. Any per-camera file may be missing (a
// camera that failed calibration, a run without `compare`, no intersect stage yet): the data says
// what is missing instead of failing. A file that is present but malformed is an input error naming
// the file, line and field (the readers of each format do that).
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gnss/formats/pole_survey_csv.hpp"
#include "gnss/time/utc_time.hpp"
#include "gnss/track/lamp_track.hpp"
#include "pipeline/io/calibrate_record.hpp"
#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/io/intersection_csv.hpp"
#include "pipeline/io/lamp_track_adjusted_csv.hpp"
#include "pipeline/io/methods_csv.hpp"
#include "pipeline/io/network_json.hpp"
#include "pipeline/io/residuals_csv.hpp"
#include "pipeline/io/trajectory_csv.hpp"
#include "vision/camera/calibration_result.hpp"

namespace rangecal {

/// `gnss/lamp_track.csv` in brief (the mission section).
struct LampTrackSummary {
  std::size_t epochs = 0;
  UtcTime start, end;
};

/// Everything the report knows about one camera of the config.
struct CameraReportData {
  std::string id;
  std::optional<CalibrationResult> calibration;      ///< absent: calibration.json missing
  std::optional<std::vector<Correspondence>> pairs;  ///< absent: correspondences.csv missing
  /// absent: residuals.csv missing (not calibrated); its lamp rows follow `pairs` one to one
  std::optional<std::vector<ResidualRow>> residuals;
  std::optional<std::vector<MethodRow>> methods;  ///< absent: methods.csv missing (no `compare`)
  /// run.json calibrate counts "cameras.<cam>.failed": why the calibrate stage gave up on the camera.
  std::string calibration_failure;
  /// run.json calibrate counts "cameras.<cam>.warnings": calibration.json's warnings as codes, in
  /// its order (empty when run.json has none).
  std::vector<WarningCodeRecord> warning_codes;
  /// The PPK error model the calibration weighed the fixes by, which the lamp residuals' noise model
  /// takes (lamp_residuals.hpp): network.json's `statistics.ppk_error_model` for a network
  /// calibration, calibration.json's `details.ppk_error_model` for a bundle under a configured
  /// model; absent: white, the `.pos` sd as written.
  std::optional<PpkErrorModel> ppk_model;
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
  /// trajectory.csv as the trajectory stage wrote it (pipeline/io/trajectory_csv.hpp); absent: the
  /// file is missing.
  std::optional<std::vector<TrajectoryRow>> trajectory;
  std::vector<StageWarnings> stage_warnings;  ///< stages in run.json order (sorted by name)
  /// The lamp track itself (site map); absent with `track`.
  std::optional<LampTrack> lamp_track;
  /// run.json `stages` without the report's own section (data funnel); null without run.json.
  nlohmann::json run_stages;
  /// The pole survey (site map): set by the caller from the config's `poles`; empty without one.
  std::vector<SurveyedPole> survey;
  /// σ per axis of a pole pick (px, the config's intersect.pick_sigma_px): the error bars' σ.
  double pick_sigma_px = 0.5;
  /// The lamp centroid σ the calibration assumed (px, kDefaultPixelSigmaPx): the noise model.
  double pixel_sigma_px = 0.1;
  /// The check-pole mean ΔR bar (m): the config's intersect.bar_mean_dR_m, by default rangecal's
  /// quality bar (docs/accuracy_analysis.md).
  double bar_mean_dR_m = 0.010;
  /// `gnss/lamp_track_adjusted.csv`, the network bundle's adjusted lamp track; absent: the network
  /// did not run, and the report has no network section.
  std::optional<std::vector<LampTrackAdjustedRow>> network_track;
  /// The cross blocks of network.json's joint covariance, indexed by the calibrated cameras in
  /// config order; empty unless every calibration comes from the network.
  CrossCovariances network_cross;
  /// network.json `float_epochs`: the σ with and without the float epochs; absent when none were
  /// used (or the network did not run).
  std::optional<FloatEpochsRecord> network_float_epochs;
  /// network.json `datum_floor` for the calibrated cameras (same order as network_cross); absent
  /// unless every calibration comes from the network and the file has it.
  std::optional<NetworkDatumFloor> network_datum_floor;
  /// run.json `stages.calibrate.counts.network` (the network's statistics); absent without it.
  std::optional<NetworkStatisticsRecord> network_statistics;
  /// run.json `stages.calibrate.counts.method_choice` (docs/config.md "Default method"): the
  /// method the default rule chose and why; empty when the config named the method.
  std::string method_choice, method_choice_why;
};

/// The calibrations of `d`'s cameras that have one, in config order.
std::vector<const CalibrationResult*> calibrated_cameras(const ReportData& d);

/// network.json's cross blocks for calibrated_cameras(d), or null (the cameras independent).
const CrossCovariances* network_cross_or_null(const ReportData& d);

/// Reads `output_dir` for the given cameras. Missing files are recorded as absent; malformed files
/// throw rangecal::Error (kind input) naming file, line and field.
ReportData read_report_data(const std::string& output_dir, const std::string& mission,
                            const std::vector<std::string>& camera_ids);

}  // namespace rangecal
