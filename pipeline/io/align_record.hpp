#pragma once
// The align stage's record: run.json `stages.align.counts` (docs/outputs.md, docs/alignment.md). One
// writer and one reader, so the stage, the report and the console summary share the keys:
//   <camera id>  {epochs, frames, epochs_outside_frames, frames_picked, frames_aligned,
//                 rejected_offset, rejected_gap, rejected_outside_track, mean_dt_s, mean_abs_dt_s,
//                 max_abs_dt_s, max_speed_mps, worst_position_error_m, worst_position_error_frame,
//                 time_source[, clock {nominal_start_utc, offset_s, offset_sd_s, rate_ppm, rate_sd_ppm,
//                 mid_offset_sd_s, span_s, rms_px, points, blocks, variable_frame_rate,
//                 worst_block_deviation_s, wander_sd_s, search_best_score_px, search_other_score_px,
//                 search_other_offset_s}]}
// The alignment step reports in AlignReport (pipeline/steps/align_frames.hpp fills it).
#include <cstddef>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
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

/// The clock of a camera without time code, as estimated (pipeline/steps/camera_clock.hpp; docs/alignment.md
/// "Cameras without time code"): t = n + offset + rate·(n − n₀).
struct ClockRecord {
  std::string nominal_start_utc;  ///< n₀, ISO 8601
  double offset_s = 0;
  double offset_sd_s = 0;
  double rate_ppm = 0;  ///< rate × 10⁶
  double rate_sd_ppm = 0;
  double mid_offset_sd_s = 0;  ///< 1σ of the correction at the record's middle
  double span_s = 0;
  double rms_px = 0;
  std::size_t points = 0;
  std::size_t blocks = 0;
  bool variable_frame_rate = false;
  double worst_block_deviation_s = 0;
  double search_best_score_px = 0;
  double search_other_score_px = 0;
  double search_other_offset_s = 0;
  double track_sd_s = 0;   ///< the lamp track's share of the σ (its sd along the path over the speed)
  double wander_sd_s = 0;  ///< the blocks' scatter about the line beyond their σ (a variable frame rate)
  double readout_s = 0;    ///< a rolling shutter's readout (0: global shutter or not estimated)
  double readout_sd_s = 0;
};

/// One camera's line: its alignment and where its frame times came from.
struct AlignCameraRecord {
  AlignReport report;
  std::string time_source;  ///< vision/frames/frame_source.hpp FrameSource::time_source, or a track's
  std::optional<ClockRecord> clock;  ///< a camera whose clock was estimated
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
