#pragma once
// A planned network with sharper images, made in the data: every observation's σ (lamp centroid,
// pole pick) divided by `factor`. The tests' independent route to the datum floor, which
// network_cramer_rao_bound's `image_factor` and the run's datum_floor_image_factor reach by
// scaling the whitening instead (pipeline/analysis/network_plan.hpp, docs/accuracy_analysis.md).
#include "pipeline/analysis/network_plan.hpp"

namespace rangecal::test {

inline PlannedNetwork with_sharper_images(PlannedNetwork n, double factor) {
  for (NetworkObservation& ob : n.observations) ob.pixel_sigma_px /= factor;
  return n;
}

}  // namespace rangecal::test
