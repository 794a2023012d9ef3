#pragma once
// The calibration-only intersection σ a run's calibrations give over the flight volume
// (pipeline/report/intersection_prediction.hpp, on a horizontal slice), and the same at the
// network's datum floor (network.json `datum_floor`, docs/accuracy_analysis.md "Datum floor"): the
// verdict of report.html and summary.json's `prediction` both read it.
//
// The slice covers the lamp track's and the poles' horizontal extent (10 % margin, at least 1 m) at
// the mean height of the intersected check poles, else the median lamp height; 36 × 28 cells.
#include <limits>
#include <optional>

#include "pipeline/report/intersection_prediction.hpp"
#include "pipeline/report/report_data.hpp"

namespace rangecal {

/// Minimum, median and maximum of a slice's σ (m) over the cells at least two cameras see (n).
struct SliceStats {
  int n = 0;
  double min = std::numeric_limits<double>::quiet_NaN();
  double median = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
};
SliceStats slice_stats(const IntersectionSigmaSlice& slice);

struct FlightVolumeSigma {
  /// The calibrations' (with network.json's cross blocks when every calibration is the network's);
  /// absent with fewer than two calibrations or nothing to place the slice.
  std::optional<IntersectionSigmaSlice> slice;
  SliceStats stats;
  /// The same cells at the datum floor; absent without a floor in network.json.
  std::optional<IntersectionSigmaSlice> datum_floor;
  SliceStats datum_floor_stats;         ///< over the cells where both slices have a σ
  double datum_floor_image_factor = 0;  ///< network.json datum_floor.image_factor
  /// Median σ over median floor σ on the same cells; NaN without a floor (or a floor of 0).
  double over_datum_floor = std::numeric_limits<double>::quiet_NaN();
};

FlightVolumeSigma flight_volume_sigma(const ReportData& d);

/// Within this ratio of its datum floor the calibration is read as limited by the datum (the PPK
/// fixes and control), not by the images: the images' own share, √(1.25² − 1) = 0.75 of the floor,
/// is then smaller than the datum's (docs/accuracy_analysis.md "Datum floor").
inline constexpr double kDatumLimitedRatio = 1.25;

}  // namespace rangecal
