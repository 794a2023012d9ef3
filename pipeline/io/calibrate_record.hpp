#pragma once
// The calibrate stage's record: run.json `stages.calibrate.counts` (docs/outputs.md). One writer and
// one reader, so the stage, the report and the console summary share the keys:
//   cameras.<id>     per camera of the config, {pairs, control_poles, failed} when its calibration
//                    failed, else {pairs, control_poles, method, rms_px, n_used, n_rejected,
//                    opencv_fit_max_px, opencv_undistort_max_px, dlt_only_rms_px, dlt_only_max_px,
//                    dlt_profile_max_px, exports_refused [text], method_time_s {method: s},
//                    warnings [{kind, camera, parameters}]}
//   network          the network's statistics (pipeline/io/network_json.hpp), when it ran
//   method_choice    {method, shared_epochs, why}: the default rule's choice (docs/config.md
//                    "Default method"), when the config named no method
// Camera ids live under `cameras`, apart from the mission-level keys.
#include <cstddef>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "optim/bundle/calibration_warning.hpp"

namespace rangecal {

/// One of calibration.json's warnings as a code (optim/bundle/calibration_warning.hpp): its kind,
/// the camera and the parameters it is about; the text is calibration.json's, at the same index.
struct WarningCodeRecord {
  CalibrationWarningKind kind = CalibrationWarningKind::poorly_determined;
  std::string camera;
  std::vector<CameraParameter> parameters;
};

/// One camera's line: what went in, and what the method made of it (or why it failed).
struct CalibrateCameraRecord {
  std::size_t pairs = 0;          ///< lamp pairs (correspondences.csv rows)
  std::size_t control_poles = 0;  ///< control-pole observations added to them
  std::string failed;             ///< non-empty: why it could not be calibrated; nothing below is set
  std::string method;             ///< the method whose result calibration.json holds
  double rms_px = std::numeric_limits<double>::quiet_NaN();  ///< over the observations used; null: none
  int n_used = 0, n_rejected = 0;
  /// How far the exports reproduce the per-camera method's camera (px,
  /// vision/camera/opencv_camera_export.hpp, dlt_export.hpp); dlt_profile_max_px is the larger of the
  /// profile's and its undistortion's.
  double opencv_fit_max_px = 0, opencv_undistort_max_px = 0;
  double dlt_only_rms_px = 0, dlt_only_max_px = 0, dlt_profile_max_px = 0;
  /// The export files not written because they cannot reproduce the camera (file name: why).
  std::vector<std::string> exports_refused;
  std::map<std::string, double> method_time_s;  ///< wall time of each per-camera method run (s, 0.1 ms)
  std::vector<WarningCodeRecord> warnings;      ///< calibration.json's warnings, coded, in its order
};

/// The codes of `warnings`, in order.
std::vector<WarningCodeRecord> warning_codes(const std::vector<CalibrationWarning>& warnings);

/// The default rule's choice (docs/config.md "Default method").
struct MethodChoiceRecord {
  std::string method;  ///< network | bundle
  std::size_t shared_epochs = 0;
  std::string why;
};

struct CalibrateRecord {
  std::map<std::string, CalibrateCameraRecord> cameras;  ///< by camera id
  /// network_statistics_json's object (read with parse_network_statistics_json); null: no network.
  nlohmann::json network;
  std::optional<MethodChoiceRecord> method_choice;  ///< absent: the config named the method
  /// The held-out check of an estimated PPK model (pipeline/steps/held_out_prediction.hpp), as
  /// held_out_scores_json wrote it; null when it did not run.
  nlohmann::json held_out;
  /// Each camera's lens set chosen by significance and the rim (pipeline/steps/lens_selection.hpp), as
  /// lens_selection_json wrote it; null when it did not run.
  nlohmann::json lens_selection;
};

/// The record as run.json holds it.
nlohmann::json calibrate_record_json(const CalibrateRecord& r);

/// Parses `j` as calibrate_record_json wrote it. `path` and `field` (e.g.
/// "stages.calibrate.counts") name it in messages: a value of the wrong type throws rangecal::Error
/// (input) naming `field.<key>`. Keys it does not know are left alone; a missing one keeps its
/// default.
CalibrateRecord parse_calibrate_record(const nlohmann::json& j, const std::string& path,
                                       const std::string& field);

}  // namespace rangecal
