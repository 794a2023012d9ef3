#pragma once
// The align stage's record: run.json `stages.align.counts` (docs/outputs.md, docs/alignment.md). One
// writer and one reader, so the stage, the report and the console summary share the keys:
//   <camera id>  {epochs, frames, epochs_outside_frames, frames_picked, frames_aligned,
//                 rejected_offset, rejected_gap, rejected_outside_track, mean_dt_s, mean_abs_dt_s,
//                 max_abs_dt_s, max_speed_mps, worst_position_error_m, worst_position_error_frame,
//                 time_source}
// The alignment step reports in AlignReport (pipeline/steps/align_frames.hpp fills it).
#include <cstddef>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace rangecal {

/// One camera's alignment: counts and time-mismatch statistics (pipeline/steps/align_frames.hpp, step 4).
struct AlignReport {
  std::size_t epochs = 0;                 ///< lamp-track epochs in
  std::size_t frames = 0;                 ///< frame stamps in
  std::size_t epochs_outside_frames = 0;  ///< epochs outside the frames' time span (step 1)
  std::size_t frames_picked = 0;          ///< distinct frames picked by some epoch
  std::size_t frames_aligned = 0;         ///< kept
  std::size_t rejected_offset = 0;
  std::size_t rejected_gap = 0;
  std::size_t rejected_outside_track = 0;
  double mean_dt_s = 0;      ///< mean Δt over kept frames (s, signed)
  double mean_abs_dt_s = 0;  ///< mean |Δt| (s)
  double max_abs_dt_s = 0;   ///< max |Δt| (s)
  double max_speed_mps = 0;  ///< max lamp speed at a kept frame (m/s)
  /// max over kept frames of speed × |Δt| (m): the error interpolation avoids.
  double worst_position_error_m = 0;
  std::int64_t worst_position_error_frame = -1;  ///< the frame where it occurs (−1: none)
};

/// One camera's line: its alignment and where its frame times came from.
struct AlignCameraRecord {
  AlignReport report;
  std::string time_source;  ///< vision/frames/frame_source.hpp FrameSource::time_source
};

struct AlignRecord {
  std::map<std::string, AlignCameraRecord> cameras;  ///< by camera id
};

/// The record as run.json holds it: one object per camera id.
nlohmann::json align_record_json(const AlignRecord& r);

/// Parses `j` as align_record_json wrote it. `path` and `field` (e.g. "stages.align.counts") name it
/// in messages: a value of the wrong type throws rangecal::Error (input) naming `field.<camera>.<key>`.
/// A missing key keeps its default.
AlignRecord parse_align_record(const nlohmann::json& j, const std::string& path, const std::string& field);

}  // namespace rangecal
