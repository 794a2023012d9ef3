#pragma once
// The (lamp ENU, lamp pixel) pairs of one camera (docs/frames_and_detection.md → §4.4): each aligned frame in
// which the lamp was found, with the lamp's interpolated position, its 1σ and its velocity at the frame's UTC
// (pipeline/steps/align_frames.hpp) and the detected centroid.
#include <vector>

#include "pipeline/io/correspondences_csv.hpp"
#include "pipeline/steps/align_frames.hpp"
#include "vision/detection/lamp_detector.hpp"

namespace rangecal {

/// `aligned` and `detections` are the same frames in the same order (one detection per aligned
/// frame); frames whose detection is not usable give no pair.
std::vector<Correspondence> lamp_pairs(const std::vector<AlignedFrame>& aligned,
                                       const std::vector<LampDetection>& detections);

}  // namespace rangecal
