#pragma once
// Lamp detection (docs/frames_and_detection.md; seed 002 §2.2 — a bright point lamp on the UAV): per frame a
// full-frame search for point-like candidates with sub-pixel centroids, then a sequence-level pass
// that rejects static lights and resolves frames with several candidates by the lamp's motion.
// Algorithm and thresholds: docs/frames_and_detection.md.
//
// Per frame (find_lamp_candidates), integer work on the native pixels except in small windows:
//   1. noise σ: robust (median absolute) horizontal pixel differences on every 32nd row;
//   2. 16×16 block max and mean in one pass (SSE2 for 8-bit);
//   3. a block is a candidate when max > mean + k_detect·σ; its background is the median of the
//      3×3 neighbouring block means (robust to the lamp itself; follows a sky gradient);
//   4. region growing from the block's brightest pixel over pixels > background + k_grow·σ;
//   5. classification: hot pixel (area < min_area or a lone spike), extended, edge, low SNR;
//   6. sub-pixel position: least-squares fit of a pixel-integrated Gaussian + constant background
//      over a window about the peak, saturated pixels excluded (seed 002 needs the lamp image
//      centre; the fit is unbiased where a thresholded centroid is not); intensity-weighted
//      centroid as the fallback.
#include <cstdint>
#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "vision/detection/detections_csv.hpp"
#include "vision/frames/image_frame.hpp"

namespace rangecal {

class FrameSource;

struct LampDetectorOptions {
  double k_detect = 6.0;              ///< block max above background, in noise σ, to look closer
  double k_grow = 3.0;                ///< blob membership threshold above background, noise σ
  double min_snr = 10.0;              ///< a lamp's peak must be ≥ min_snr·σ above background
  int min_area = 3;                   ///< blobs with fewer pixels are hot pixels / noise spikes
  double min_neighbour_ratio = 0.15;  ///< mean 4-neighbour / peak (above bg) below this → hot pixel
  double min_sigma_px = 0.45;         ///< fitted PSF σ below this → hot pixel (not a lens-blurred point)
  double max_sigma_px = 6.0;          ///< fitted PSF σ above this → extended object, not the lamp
  int max_blob_px = 2500;             ///< a blob with more pixels is extended (cloud edge, sun glint)
  int max_candidates = 16;            ///< per frame, brightest kept
  int edge_margin_px = 2;             ///< a peak closer than this to the border → rejected_edge
  // Sequence level
  double static_radius_px = 1.5;     ///< candidates this close in different frames are "the same light"
  double static_min_fraction = 0.2;  ///< … static when seen in ≥ this fraction of the frames
  int static_min_frames = 5;         ///< … and in at least this many frames
  double motion_gate_px = 8.0;       ///< max distance from the motion prediction for ok_by_motion
  double motion_max_gap_s = 2.0;     ///< neighbours farther in time than this do not predict
};

enum class CandidateKind { lamp, hot_pixel, extended, edge, low_snr };

struct LampCandidate {
  double u = 0, v = 0;    ///< sub-pixel position (px)
  double peak = 0;        ///< brightest pixel − background (DN)
  double background = 0;  ///< local background (DN)
  int area = 0;           ///< blob pixels above the growth threshold
  double snr = 0;         ///< peak / noise σ
  double sigma_px = 0;    ///< fitted PSF σ (0 when not fitted)
  int saturated_px = 0;   ///< pixels at the saturation level
  bool fitted = false;    ///< position from the Gaussian fit (else intensity-weighted centroid)
  CandidateKind kind = CandidateKind::lamp;
};

struct FrameCandidates {
  std::int64_t frame = 0;
  UtcTime utc;
  bool loaded = true;  ///< false: frame skipped (missing_frame)
  std::string skip_reason;
  double noise_sigma = 0;                 ///< DN
  std::vector<LampCandidate> candidates;  ///< brightest first
};

/// Full-frame candidate search on one CV_8UC1 / CV_16UC1 frame with `bits` significant bits.
/// Thread-safe; no allocation per call after the first on a thread.
FrameCandidates find_lamp_candidates(const cv::Mat& image, int bits, const LampDetectorOptions& options);

/// Sequence pass over candidates in frame (time) order: static-light rejection, per-frame status,
/// then motion consistency for frames with several candidates. Output in the same order. On one
/// frame this is the single-frame decision: static lights and motion need other frames.
std::vector<LampDetection> resolve_lamp_sequence(const std::vector<FrameCandidates>& frames,
                                                 const LampDetectorOptions& options);

/// Decodes source entries `indices` (in that order; only those frames are decoded) and detects the
/// lamp, in parallel with TBB over `threads` threads (0 = all); the result is in `indices` order
/// and identical for any thread count. Missing frames the source allows to skip get missing_frame.
std::vector<LampDetection> detect_lamp(const FrameSource& source, const std::vector<std::size_t>& indices,
                                       const LampDetectorOptions& options, int threads,
                                       const std::function<void()>& on_frame_done = {});

/// As above for frames already in memory (in time order).
std::vector<LampDetection> detect_lamp(const std::vector<ImageFrame>& frames,
                                       const LampDetectorOptions& options, int threads);

}  // namespace rangecal
