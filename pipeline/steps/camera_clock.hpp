#pragma once
// A camera without time code (docs/alignment.md "Cameras without time code"): its clock found from
// the data. Frame k's nominal time n_k (from a timestamps CSV or t0 + k/fps) is taken to be off by an
// offset and a rate,
//   t_k = n₀ + offset + (1 + rate)·(n_k − n₀),        n₀ the first labelled frame's nominal time,
// and both are estimated from the camera's 2-D track against the lamp track, in four steps:
//  1. Coarse search over the whole overlap: every step of offset (`coarse_step_s`, or less: half the
//     truncation over the labels' 90th-percentile image speed) such that at least half of
//     the frames fall inside the lamp track (or over `search_s` when given), a linear DLT (Hartley &
//     Zisserman alg. 7.1) on an even subsample of the labels, refitted once without the points beyond
//     3× its median residual, scored by its rms residual truncated at `truncate_px` (a wrong offset
//     pairs pixels with the wrong positions; no pinhole explains them).
//  2. Fine search of offset and rate together, on the same subsample: every `fine_step_s` of the
//     record's mid-point offset within ±`fine_half_width_s` of the best, every `rate_step` within
//     ±`max_rate` (a phone's clock may run 1e-3 off: 0.2 s over a 200-s record).
//  3. Refinement: the camera (f, principal point, k1, k2, pose) and a constant clock offset by the
//     bundle (optim/bundle/bundle_adjustment.hpp, its linearised clock offset: the lamp stood at
//     X − v·δ), then, the camera held, one offset per `block_s` block of frames; a weighted straight
//     line through the block offsets corrects offset and rate. Repeated until the line moves the
//     clock by less than 0.05 ms anywhere on the record.
//  3b. With a rolling shutter (`estimate_readout`): each label's time gains (v/(H−1) − ½)·readout, v
//     its row; the readout is corrected in the same loop by least squares on the labels' residuals
//     along their image velocity, the camera and the line held, its σ from the blocks' scatter.
//  4. σ from the line fit, scaled by the blocks' scatter about it (√(χ²/dof) when above 1): label
//     errors are correlated from frame to frame, so the per-frame Hessian would claim ten times the
//     precision the blocks show. A block whose offset is well determined (σ ≤ `vfr_block_sd_s`) and
//     lies more than `vfr_threshold_s` off the line flags a variable frame rate: one offset and rate
//     then cannot follow the camera's clock, and the frames carry errors of that size.
// The σ also carry the lamp track's own error along the lamp's path (its fixes' sd along the velocity
// over the speed): a PPK error correlated over the record shifts the lamp along its path, which the
// labels cannot tell from a clock offset. The clock's σ is not carried into the calibration's covariance: an
// offset error σ moves the lamp by |v|·σ along its path (docs/alignment.md).
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "gnss/time/utc_time.hpp"
#include "gnss/track/hermite_interpolation.hpp"
#include "vision/camera/sensor_geometry.hpp"

namespace rangecal {

/// One label of the camera: its frame, the frame's nominal time and the pixel.
struct ClockObservation {
  std::int64_t frame = 0;
  UtcTime nominal;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  ///< px, docs/conventions.md
};

struct ClockSearchOptions {
  /// The offsets searched (s, added to the nominal times); nullopt: the whole overlap (step 1).
  std::optional<std::pair<double, double>> search_s;
  /// The coarse step's upper limit: smaller where the labels move fast in the image (step 1).
  double coarse_step_s = 0.2;
  double fine_step_s = 0.01;
  double fine_half_width_s = 0.2;  ///< ± the coarse step: the best basin's neighbours
  double max_rate = 2e-3;          ///< rates searched in step 2 (±; consumer cameras reach 1e-3)
  double rate_step = 5e-5;         ///< 50 ppm: 5 ms over 100 s, within the refinement's reach
  double truncate_px = 25;         ///< residuals beyond this count as this in the search's score
  std::size_t subsample = 300;     ///< labels used per coarse try (evenly spaced)
  double block_s = 20;             ///< block length for the offset line (s of nominal time)
  std::size_t min_block_points = 15;
  double pixel_sigma_px = 1;       ///< the labels' σ the refinement weighs with (px)
  double vfr_block_sd_s = 0.003;   ///< a block this well determined …
  double vfr_threshold_s = 0.008;  ///< … and this far off the line flags a variable frame rate
  /// A rolling shutter's readout (s): the value held, or the start when estimated (step 3b).
  double readout_s = 0;
  bool estimate_readout = false;
  /// A second basin farther than 2 s from the best that scores within this factor of it makes the
  /// offset ambiguous (an error naming both).
  double ambiguity_ratio = 1.5;
};

/// One block's own offset, the camera held (step 3).
struct ClockBlock {
  double mid_s = 0;        ///< block centre, s of nominal time after n₀
  double deviation_s = 0;  ///< the block's own correction less the estimated clock's at mid_s (s)
  double sd_s = 0;         ///< its 1σ (s)
  std::size_t points = 0;
};

struct CameraClock {
  UtcTime nominal_start;   ///< n₀
  double offset_s = 0;     ///< t − n at n₀ (s)
  double offset_sd_s = 0;  ///< 1σ (s)
  double rate = 0;         ///< dimensionless (1e-4 = 100 ppm: the camera's clock runs slow by that)
  double rate_sd = 0;
  double span_s = 0;           ///< nominal time from the first to the last label (s)
  double mid_offset_sd_s = 0;  ///< 1σ of the correction at the record's middle (s): the best-known instant
  /// The lamp track's share of those σ (s): its fixes' sd along the lamp's path over the speed (median).
  double track_sd_s = 0;
  double rms_px = 0;                 ///< the refined camera's rms residual over the labels it kept (px)
  std::size_t points = 0;            ///< labels inside the lamp track at the final clock
  double search_best_score_px = 0;   ///< step 1's truncated rms at the best basin
  double search_other_score_px = 0;  ///< … at the best offset more than 2 s away (0: none searched)
  double search_other_offset_s = 0;
  std::vector<ClockBlock> blocks;
  bool variable_frame_rate = false;
  double worst_block_deviation_s = 0;  ///< the largest |block − line| among well-determined blocks (s)
  /// The blocks' scatter about the line beyond their own σ (s): how far a frame's time may be off in
  /// a stretch the line was not fitted to (a variable frame rate's wander); 0 for a steady clock.
  double wander_sd_s = 0;
  /// A rolling shutter's readout (s): row v is exposed (v/(H−1) − ½)·readout after the frame's time
  /// (the middle row's); 0 for a global shutter or when not estimated. Its σ from the blocks.
  double readout_s = 0;
  double readout_sd_s = 0;
  int image_height_px = 2;  ///< H

  /// The estimated true time of a frame whose nominal time is `nominal` (its middle row).
  UtcTime time_of(UtcTime nominal) const;
  /// The estimated true time of a label in row `v_px` of that frame (the readout's share added).
  UtcTime label_time(UtcTime nominal, double v_px) const;
  /// The 1σ of time_of(nominal) (s): the line's σ there (offset, rate and their correlation through
  /// mid_offset_sd_s) and the wander.
  double time_sd_s(UtcTime nominal) const;
};

/// The 1σ (s) of a clock's correction `since_start_s` of nominal time after n₀: the line's variance
/// there, var(a) + 2s·cov(a, b) + s²·var(b), with cov(a, b) recovered from the σ at the record's
/// middle (s = span/2), plus the wander's.
double clock_time_sd_s(double offset_sd_s, double rate_sd, double mid_offset_sd_s, double span_s,
                       double since_start_s, double wander_sd_s);

/// Estimates the clock (method in the header comment). `sensor` gives the image size and pixel pitch
/// the DLT's camera is expressed in. Throws rangecal::Error (input, naming `source`, e.g. the track
/// file): fewer than 20 labels; no offset in the search range that puts half of the labels inside the
/// lamp track; an ambiguous offset (two basins within ambiguity_ratio); a refinement that fails.
CameraClock estimate_camera_clock(const HermiteTrack& track, const std::vector<ClockObservation>& labels,
                                  const SensorGeometry& sensor, const ClockSearchOptions& options,
                                  const std::string& source);

}  // namespace rangecal
