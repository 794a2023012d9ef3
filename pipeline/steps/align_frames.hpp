#pragma once
// The align stage (docs/alignment.md; seed 002 §2.4 "boundary alignment and frame decimation"): for one
// camera, which frames to use and where the lamp was at each frame's exact UTC.
//
// Method (documented in docs/alignment.md):
//  1. Boundary alignment: only lamp-track epochs within [first frame − max_frame_offset_s,
//     last frame + max_frame_offset_s] take part; the others are counted (epochs_outside_frames).
//  2. Frame decimation: each taking-part epoch picks its nearest frame (the two frames bracketing
//     it in time; exact ties go to the earlier frame). When that frame cannot be interpolated (it
//     lies in a track gap or beyond the track's end) and the frame on the other side of the epoch
//     can and lies within max_frame_offset_s, the other one is taken. A frame picked by several
//     epochs is kept once, with its nearest picking epoch.
//  3. Every picked frame is kept when |frame − epoch| ≤ max_frame_offset_s and the track can be
//     interpolated at the frame's UTC (HermiteTrack: cubic Hermite, never across a gap);
//     otherwise it is rejected with its reason.
//  4. Report: count, mean and max |Δt| over kept frames (Δt = frame − epoch), and the worst
//     position error that using the epoch's position instead of interpolating would have caused:
//     max over kept frames of |velocity at the frame| × |Δt|.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "gnss/time/span_comparison.hpp"
#include "gnss/time/utc_time.hpp"
#include "gnss/track/lamp_track.hpp"
#include "pipeline/io/align_record.hpp"
#include "pipeline/io/aligned_csv.hpp"

namespace rangecal {

/// One frame of one camera: its index in the source (image list, video, .cine) and its UTC.
struct FrameStamp {
  std::int64_t frame = 0;
  UtcTime utc;
};

struct AlignOptions {
  double max_frame_offset_s = 0.005;         ///< config align.max_frame_offset_s (s, > 0)
  double max_gap_s = 0.5;                    ///< config gnss.max_gap_s (s, > 0)
  std::string track_source = "lamp track";   ///< names the track in error messages (a path)
  std::string frames_source = "frame list";  ///< names the frame list in error messages (a path)
};

enum class FrameRejection {
  offset_exceeded,  ///< no lamp-track epoch within max_frame_offset_s
  in_gap,           ///< the frame's UTC lies inside a track gap longer than max_gap_s
  outside_track,    ///< the frame's UTC lies before the first or after the last epoch
};
const char* to_string(FrameRejection r);

struct RejectedFrame {
  std::int64_t frame = 0;
  UtcTime utc;
  double dt_s = 0;  ///< frame UTC − the epoch that picked it (s)
  FrameRejection reason = FrameRejection::offset_exceeded;
  std::string detail;  ///< human-readable, with the numbers
};

struct AlignResult {
  std::vector<AlignedFrame> aligned;    ///< in frame order
  std::vector<RejectedFrame> rejected;  ///< in frame order
  AlignReport report;                   ///< pipeline/io/align_record.hpp
};

/// Aligns one camera's frames to the lamp track (method in the header comment). `frames` must be
/// strictly increasing in both frame index and UTC; the track's epochs strictly increasing.
/// Throws rangecal::Error: (input) empty track, empty frame list, frames or epochs out of order;
/// (usage) non-positive max_frame_offset_s or max_gap_s.
AlignResult align_frames(const LampTrack& track, const std::vector<FrameStamp>& frames,
                         const AlignOptions& options);

/// One camera's frames as the align stage saw them, for its error message.
struct CameraFrameSpan {
  std::string camera_id;
  UtcSpan frames;  ///< first and last frame stamp (UTC)
};

/// Why no camera has a frame aligned with the lamp track, for the align stage's error: the lamp
/// track's UTC span, each camera's frame span and, per camera, the overlap or the gap with its likely
/// cause (compare_spans, gnss/time/span_comparison.hpp: days apart → camera clock not set, GPS − UTC
/// leap seconds → GPST vs UTC, whole hours → a time zone). When the spans overlap, it says the frames
/// fall in track gaps or farther than `max_frame_offset_s` (s) from every epoch.
std::string explain_no_alignment(const UtcSpan& track, const std::vector<CameraFrameSpan>& cameras,
                                 double max_frame_offset_s);

}  // namespace rangecal
