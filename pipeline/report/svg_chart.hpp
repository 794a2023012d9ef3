#pragma once
// The building blocks of report.html's charts (pipeline/report/report_plots.hpp): a plot area with
// linear axes, round ticks and labelled axes, colour maps with contours and a colour bar, and
// segment clipping. Every chart is an <svg class="plot"> holding one rect.area (the plot area) and
// one g.data whose elements all lie inside it (the report test checks this in a browser); ticks,
// labels (text.xlabel, text.ylabel, "name (unit)") and keys lie outside the area, inside the svg.
// Numbers are printed with fixed formats, so the same data gives the same bytes.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace rangecal {

/// Data → drawing coordinates of one plot area.
struct ChartAxes {
  double left = 0, top = 0, width = 1, height = 1;  ///< plot area (drawing units)
  double x0 = 0, x1 = 1;                            ///< data at the left and right edges
  double y0 = 0, y1 = 1;                            ///< data at the bottom and top edges (y up)
  bool y_down = false;                              ///< image axes: y0 at the top (v down)
  double X(double x) const { return left + (x - x0) / (x1 - x0) * width; }
  double Y(double y) const {
    const double t = (y - y0) / (y1 - y0);
    return y_down ? top + t * height : top + height - t * height;
  }
  double right() const { return left + width; }
  double bottom() const { return top + height; }
};

/// Round tick values (1, 2, 5 × 10^k steps) within [lo, hi], about `n` of them.
std::vector<double> nice_ticks(double lo, double hi, int n);

/// "%.2f" of a drawing coordinate.
std::string svg_num(double x);
/// A short tick label: "%g" with at most 4 significant digits.
std::string tick_label(double x);

/// `<svg class="plot" id=… width height viewBox><title>…</title>` (text escaped).
std::string svg_open(double width, double height, const std::string& id, const std::string& title);

/// rect.area, ticks and their labels on the left and bottom (or top for image axes), and the axis
/// labels text.xlabel and text.ylabel (escaped; write them as "name (unit)").
std::string svg_axes(const ChartAxes& a, const std::string& x_label, const std::string& y_label,
                     int n_ticks_x = 6, int n_ticks_y = 5, double ylabel_offset = 40);

/// A perceptually ordered colour (viridis-like) for t in [0, 1] (clamped), as "#rrggbb".
std::string sequential_colour(double t);
/// Blue (−1) – white (0) – red (+1) for t in [−1, 1] (clamped).
std::string diverging_colour(double t);

/// Filled cells: values (ny × nx, row 0 at y_centres[0]) at cell centres spaced evenly, coloured by
/// value / vmax (NaN cells left empty). Each cell is a rect.cell carrying `data-value` ("%.6g").
std::string svg_cells(const ChartAxes& a, const std::vector<double>& x_centres,
                      const std::vector<double>& y_centres, const Eigen::MatrixXd& values, double vmax);

/// Contour lines (path.contour, one per level, marching squares between cell centres) with their
/// level written at one point of each (text.contour-label).
std::string svg_contours(const ChartAxes& a, const std::vector<double>& x_centres,
                         const std::vector<double>& y_centres, const Eigen::MatrixXd& values,
                         const std::vector<double>& levels);

/// A vertical colour bar (g.colourbar) from 0 to vmax at (x, y), size w × h, labelled `label`.
std::string svg_colour_bar(double x, double y, double w, double h, double vmax, const std::string& label);

/// Clips segment p→q to the rectangle [x0, x1] × [y0, y1] (drawing units; Liang–Barsky). Returns
/// false when nothing is left; `*clipped` says whether q (the tip) was cut.
bool clip_segment(double x0, double y0, double x1, double y1, Eigen::Vector2d* p, Eigen::Vector2d* q,
                  bool* clipped);

/// Contour levels: round values (nice_ticks) strictly between the smallest and largest finite
/// value, at most `n`.
std::vector<double> contour_levels(const Eigen::MatrixXd& values, int n);

}  // namespace rangecal
