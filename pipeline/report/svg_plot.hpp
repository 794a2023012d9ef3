#pragma once
// Small inline-SVG plots for report.html (docs/outputs.md): the lamp track on the image (seed 002
// Fig. 6), residual vectors and a histogram. Pure functions of their inputs returning SVG text;
// every coordinate is printed with "%.2f", so the same data gives the same bytes. Elements carry
// class names (documented per function) so styles and tests can find them.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace rangecal {

/// The image area a plot shows: pixels (u right, v down), top-left pixel centre (0, 0).
struct PlotFrame {
  int width_px = 0;
  int height_px = 0;
};

/// The largest 1, 2 or 5 × 10^k not above x (x > 0); 0 for x ≤ 0 or not finite. Used for scale
/// bars and histogram bin widths so their labels are round numbers.
double nice_floor(double x);

/// Seed 002 Fig. 6: the image frame (rect.frame) with the observed lamp pixels joined in time
/// order (polyline.track), each observed pixel (circle.obs; circle.rejected for pairs the
/// calibration rejected) and the reprojected position of its world point through the calibrated
/// camera (path.proj, a small cross). `reprojected` may be empty (camera not calibrated);
/// otherwise it matches `observed` in size. `used` matches `observed` or is empty (all used).
/// `breaks`: indices (increasing) where the track restarts (a new ascent after a gap in time), so
/// one polyline is drawn per flown segment. `id` becomes the svg element's id.
std::string svg_lamp_track(const PlotFrame& frame, const std::vector<Eigen::Vector2d>& observed,
                           const std::vector<Eigen::Vector2d>& reprojected, const std::vector<bool>& used,
                           const std::vector<std::size_t>& breaks, const std::string& id);

/// Residual vectors (observed − reprojected, px) drawn at the observed pixels (line.resid), scaled
/// so the largest is about a tenth of the image width, with a scale bar (line.scalebar) of a round
/// length in pixels of residual and its label. Same sizes as `at`.
std::string svg_residual_vectors(const PlotFrame& frame, const std::vector<Eigen::Vector2d>& at,
                                 const std::vector<Eigen::Vector2d>& residual, const std::string& id);

/// Histogram of `values` (≥ 0, e.g. residual norms in px) with round bin widths starting at 0:
/// bars (rect.bar), x axis ticks labelled with `x_label`, y axis counts.
std::string svg_histogram(const std::vector<double>& values, const std::string& x_label,
                          const std::string& id);

}  // namespace rangecal
