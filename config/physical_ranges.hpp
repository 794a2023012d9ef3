#pragma once
// The physical ranges every input number is checked against (docs/reliability.md, "Input ranges"),
// fixed once so that every format applies the same limits. A value outside its range is refused
// at its parser with file, line and field: it is a unit mistake, a swapped column or a corrupt
// file, never a geometry rangecal should compute with.
#include <cmath>

namespace rangecal::ranges {

/// Ellipsoidal height of anything on a test range or above it (m): the Dead Sea to the stratosphere.
constexpr double kMinHeightM = -1000;
constexpr double kMaxHeightM = 20000;
/// Half-width of the site box around the ENU origin (m), |E| and |N|: cameras on a test range look
/// at hundreds of metres to a few km; 50 km covers any range and catches unit and column mistakes.
constexpr double kSiteHalfWidthM = 50000;
/// |U| limit in the site box (m).
constexpr double kSiteHalfHeightM = 21000;
/// True when site ENU (m) lies in the site box: |E|, |N| ≤ kSiteHalfWidthM, |U| ≤ kSiteHalfHeightM.
inline bool within_site_box(double e, double n, double u) {
  return std::abs(e) <= kSiteHalfWidthM && std::abs(n) <= kSiteHalfWidthM && std::abs(u) <= kSiteHalfHeightM;
}
/// Largest standard deviation of a position (m).
constexpr double kMaxPositionSigmaM = 10000;
/// Largest speed of the UAV or a lamp (m/s).
constexpr double kMaxSpeedMps = 1000;
/// Largest lamp–antenna distance (m): the lamp hangs from the UAV that carries the antenna.
constexpr double kMaxLeverArmM = 10;
/// Largest difference between the total-station sessions' vertical lever arms (m): a total station
/// measures the two marks to a few mm, so sessions further apart than this measured different
/// things (a wrong mark, a misread target height).
constexpr double kTotalStationAgreementM = 0.02;
/// Largest image side a camera may have (px) and largest |u|, |v| a pixel coordinate may take
/// when the image size is not known where it is read.
constexpr int kMaxImageSidePx = 32768;
constexpr double kMaxPixelCoordinatePx = 1.0e5;

}  // namespace rangecal::ranges
