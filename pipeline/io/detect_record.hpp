#pragma once
// The detect stage's record: run.json `stages.detect.counts` (docs/outputs.md, docs/frames_and_detection.md).
// One writer and one reader, so the stage, the report and the console summary share the keys:
//   <camera id>  {time_source, frames_examined, by_status {status: frames}, correspondences,
//                 timestamp_check {best_offset_s, rms_at_zero_px, rms_at_best_px} when it ran}
#include <cstddef>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace rangecal {

/// The frame-stamp check's figures (pipeline/steps/timestamp_check.hpp); a DLT rms that could not
/// be computed is NaN (written as null).
struct TimestampCheckRecord {
  double best_offset_s = 0;
  double rms_at_zero_px = std::numeric_limits<double>::quiet_NaN();
  double rms_at_best_px = std::numeric_limits<double>::quiet_NaN();
};

/// One camera's line.
struct DetectCameraRecord {
  std::string time_source;  ///< vision/frames/frame_source.hpp FrameSource::time_source
  std::size_t frames_examined = 0;
  std::map<std::string, int> by_status;  ///< frames per detection status ("ok", "no_blob", ...)
  std::size_t correspondences = 0;       ///< lamp pairs (correspondences.csv rows)
  std::optional<TimestampCheckRecord> timestamp_check;  ///< absent: too few pairs to check
};

struct DetectRecord {
  std::map<std::string, DetectCameraRecord> cameras;  ///< by camera id
};

/// The record as run.json holds it: one object per camera id.
nlohmann::json detect_record_json(const DetectRecord& r);

/// Parses `j` as detect_record_json wrote it. `path` and `field` (e.g. "stages.detect.counts") name
/// it in messages: a value of the wrong type throws rangecal::Error (input) naming
/// `field.<camera>.<key>`. A missing key keeps its default.
DetectRecord parse_detect_record(const nlohmann::json& j, const std::string& path, const std::string& field);

}  // namespace rangecal
