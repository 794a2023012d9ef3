#include "pipeline/report/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "config/number_format.hpp"
#include "pipeline/report/html_escape.hpp"
#include "pipeline/report/svg_chart.hpp"

namespace rangecal {
namespace {

constexpr double kPlotWidth = 640;  // drawing width of image plots (SVG user units)
constexpr double kLeft = 52;        // room for the v ticks and axis label
constexpr double kTop = 40;         // room for the u ticks and axis label
constexpr double kRight = 16;
constexpr double kBottom = 30;  // the key line below the frame

std::string f2(double x) {
  return format_number("%.2f", x);
}

// Short label of a round number (bin edges, scale bar): at most 3 significant digits.
std::string label(double x) {
  return format_number("%.3g", x);
}

// Pixel → drawing coordinates (pixel centres at +0.5 so the frame spans [−0.5, W−0.5]).
struct ImageMap {
  double scale = 1;
  double x(double u) const { return kLeft + (u + 0.5) * scale; }
  double y(double v) const { return kTop + (v + 0.5) * scale; }
};

ImageMap image_map(const PlotFrame& f) {
  ImageMap m;
  m.scale = f.width_px > 0 ? kPlotWidth / f.width_px : 1.0;
  return m;
}

// The same mapping as ChartAxes (pixel edges −0.5 … W − 0.5, v down).
ChartAxes image_axes(const PlotFrame& f, const ImageMap& m) {
  ChartAxes a;
  a.left = kLeft;
  a.top = kTop;
  a.width = f.width_px * m.scale;
  a.height = f.height_px * m.scale;
  a.x0 = -0.5;
  a.x1 = f.width_px - 0.5;
  a.y0 = -0.5;
  a.y1 = f.height_px - 0.5;
  a.y_down = true;
  return a;
}

// Opens the svg with its frame rectangle, ticks in px and axis labels; returns the text so far and
// leaves a g.data open (close_image_svg closes it).
std::string open_image_svg(const PlotFrame& f, const ImageMap& m, const std::string& id,
                           const std::string& title) {
  const double w = kLeft + kPlotWidth + kRight, h = kTop + std::max(1, f.height_px) * m.scale + kBottom;
  std::string s = svg_open(w, h, id, title);
  s += "<rect class=\"frame\" x=\"" + f2(kLeft) + "\" y=\"" + f2(kTop) + "\" width=\"" +
       f2(f.width_px * m.scale) + "\" height=\"" + f2(f.height_px * m.scale) +
       "\" fill=\"#fafafa\" stroke=\"none\"/>\n";
  s += svg_axes(
      image_axes(f, m),
      "u (px), right; image " + std::to_string(f.width_px) + " x " + std::to_string(f.height_px) + " px",
      "v (px), down", 8, 5);
  return s + "<g class=\"data\">\n";
}

}  // namespace

double nice_floor(double x) {
  if (!(x > 0) || !std::isfinite(x)) return 0;
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  const double m = x / p;  // in [1, 10) up to rounding
  const double n = m >= 5 ? 5 : m >= 2 ? 2 : m >= 1 ? 1 : 0.5;
  return n * p;
}

std::string svg_lamp_track(const PlotFrame& frame, const std::vector<Eigen::Vector2d>& observed,
                           const std::vector<Eigen::Vector2d>& reprojected, const std::vector<bool>& used,
                           const std::vector<std::size_t>& breaks, const std::string& id) {
  const ImageMap m = image_map(frame);
  std::string s = open_image_svg(frame, m, id, "Lamp track on the image (seed 002 Fig. 6)");
  std::size_t next_break = 0;
  for (std::size_t i = 0; i < observed.size(); ++i) {
    const bool starts = i == 0 || (next_break < breaks.size() && breaks[next_break] == i);
    if (starts && i > 0) {
      s += "\"/>\n";
      ++next_break;
    }
    if (starts)
      s += "<polyline class=\"track\" fill=\"none\" stroke=\"#7aa6d6\" stroke-width=\"0.8\" points=\"";
    else
      s += " ";
    s += f2(m.x(observed[i].x())) + "," + f2(m.y(observed[i].y()));
  }
  if (!observed.empty()) s += "\"/>\n";
  // Observed: filled dots; reprojected: larger orange crosses on top, whose arms reach past the dot,
  // so both show where they coincide.
  for (std::size_t i = 0; i < observed.size(); ++i) {
    const bool ok = used.empty() || used[i];
    s += "<circle class=\"" + std::string(ok ? "obs" : "rejected") + "\" cx=\"" + f2(m.x(observed[i].x())) +
         "\" cy=\"" + f2(m.y(observed[i].y())) + "\" r=\"" + (ok ? "1.80" : "2.60") + "\" fill=\"" +
         (ok ? "#1f5fa8" : "none") + "\" stroke=\"" + (ok ? "none" : "#d62728") +
         "\" stroke-width=\"1.2\"/>\n";
  }
  for (const Eigen::Vector2d& p : reprojected) {
    const double x = m.x(p.x()), y = m.y(p.y()), a = 3.0;
    s += "<path class=\"proj\" d=\"M" + f2(x - a) + " " + f2(y - a) + "L" + f2(x + a) + " " + f2(y + a) +
         "M" + f2(x - a) + " " + f2(y + a) + "L" + f2(x + a) + " " + f2(y - a) +
         "\" stroke=\"#e07b00\" stroke-width=\"0.9\"/>\n";
  }
  s += "</g>\n";
  // The key, below the frame.
  const double ly = kTop + frame.height_px * m.scale + 18;
  s += "<g class=\"key\" font-size=\"11\"><circle cx=\"" + f2(kLeft + 4) + "\" cy=\"" + f2(ly - 4) +
       "\" r=\"1.80\" fill=\"#1f5fa8\"/><text x=\"" + f2(kLeft + 10) + "\" y=\"" + f2(ly) +
       "\">observed lamp pixel</text>";
  if (!reprojected.empty())
    s += "<path d=\"M" + f2(kLeft + 137) + " " + f2(ly - 7) + "L" + f2(kLeft + 143) + " " + f2(ly - 1) + "M" +
         f2(kLeft + 137) + " " + f2(ly - 1) + "L" + f2(kLeft + 143) + " " + f2(ly - 7) +
         "\" stroke=\"#e07b00\" stroke-width=\"0.9\"/><text x=\"" + f2(kLeft + 148) + "\" y=\"" + f2(ly) +
         "\">reprojected world point</text>";
  else
    s += "<text x=\"" + f2(kLeft + 140) + "\" y=\"" + f2(ly) + "\">(no reprojection: not calibrated)</text>";
  s += "<circle cx=\"" + f2(kLeft + 304) + "\" cy=\"" + f2(ly - 4) +
       "\" r=\"2.60\" fill=\"none\" stroke=\"#d62728\" stroke-width=\"1.2\"/><text x=\"" + f2(kLeft + 311) +
       "\" y=\"" + f2(ly) + "\">rejected by the calibration</text></g>\n";
  s += "</svg>\n";
  return s;
}

std::string svg_residual_vectors(const PlotFrame& frame, const std::vector<Eigen::Vector2d>& at,
                                 const std::vector<Eigen::Vector2d>& residual, const std::string& id) {
  const ImageMap m = image_map(frame);
  std::string s = open_image_svg(frame, m, id, "Reprojection residual vectors");
  double max_r = 0;
  for (const Eigen::Vector2d& r : residual) max_r = std::max(max_r, r.norm());
  // Drawing units per pixel of residual: the largest residual spans a tenth of the plot width.
  const double gain = max_r > 0 ? 0.1 * kPlotWidth / max_r : 1.0;
  const std::size_t n = std::min(at.size(), residual.size());
  // Clipped to the frame: a vector that would leave it ends at the edge with an open tip (circle.cut).
  const double fx0 = kLeft, fy0 = kTop, fx1 = kLeft + frame.width_px * m.scale,
               fy1 = kTop + frame.height_px * m.scale;
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector2d p(m.x(at[i].x()), m.y(at[i].y())), q = p + gain * residual[i];
    bool cut = false;
    if (!clip_segment(fx0, fy0, fx1, fy1, &p, &q, &cut)) continue;
    s += "<line class=\"resid\" x1=\"" + f2(p.x()) + "\" y1=\"" + f2(p.y()) + "\" x2=\"" + f2(q.x()) +
         "\" y2=\"" + f2(q.y()) + "\" stroke=\"#c0392b\" stroke-width=\"1\"/>\n";
    s += "<circle class=\"foot\" cx=\"" + f2(p.x()) + "\" cy=\"" + f2(p.y()) +
         "\" r=\"1.20\" fill=\"#333\"/>\n";
    if (cut)
      s += "<circle class=\"cut\" cx=\"" + f2(q.x()) + "\" cy=\"" + f2(q.y()) +
           "\" r=\"2.00\" fill=\"none\" stroke=\"#c0392b\" stroke-width=\"0.8\"/>\n";
  }
  s += "</g>\n";
  // Key: a round residual length, below the frame.
  const double bar_px = max_r > 0 ? nice_floor(max_r) : 1.0;
  const double by = kTop + frame.height_px * m.scale + 16, bx = kLeft;
  s += "<g class=\"key\"><line class=\"scalebar\" x1=\"" + f2(bx) + "\" y1=\"" + f2(by) + "\" x2=\"" +
       f2(bx + gain * bar_px) + "\" y2=\"" + f2(by) + "\" stroke=\"#000\" stroke-width=\"2\"/>\n";
  s += "<text x=\"" + f2(bx + gain * bar_px + 6) + "\" y=\"" + f2(by + 4) + "\" font-size=\"11\">" +
       label(bar_px) + " px residual (vectors magnified " + label(gain / m.scale) +
       "x; o at a tip: cut at the frame)</text></g>\n";
  s += "</svg>\n";
  return s;
}

std::string svg_histogram(const std::vector<double>& values, const std::string& x_label,
                          const std::string& id) {
  double max_v = 0;
  for (double v : values)
    if (std::isfinite(v)) max_v = std::max(max_v, v);
  // About ten round-width bins from 0 (at least one).
  const double bin = max_v > 0 ? nice_floor(max_v / 10.0) : 1.0;
  // Bin index of v; the tolerance puts a value on a bin edge (0.95 with bin 0.05, whose quotient is
  // 18.999…) into the bin it starts, as its label says.
  auto bin_of = [bin](double v) { return static_cast<std::size_t>(std::floor(v / bin + 1e-9)); };
  const std::size_t nbins = bin_of(max_v) + 1;
  std::vector<int> counts(nbins, 0);
  for (double v : values) {
    if (!std::isfinite(v) || v < 0) continue;
    const std::size_t k = std::min(nbins - 1, bin_of(v));
    ++counts[k];
  }
  const int max_c = std::max(1, *std::max_element(counts.begin(), counts.end()));
  ChartAxes a;
  a.left = 56;
  a.top = 16;
  a.width = 480 - 56 - 16;
  a.height = 240 - 16 - 46;
  a.x0 = 0;
  a.x1 = static_cast<double>(nbins) * bin;
  a.y0 = 0;
  a.y1 = max_c;
  std::string s = svg_open(480, 240, id, "Histogram: " + x_label);
  s += "<g class=\"data\">\n";
  for (std::size_t k = 0; k < nbins; ++k) {
    const double x = a.X(k * bin), w = a.X((k + 1) * bin) - x, top = a.Y(counts[k]);
    s += "<rect class=\"bar\" x=\"" + f2(x + 0.5) + "\" y=\"" + f2(top) + "\" width=\"" +
         f2(std::max(0.5, w - 1.0)) + "\" height=\"" + f2(a.bottom() - top) + "\" fill=\"#5b8fc7\"><title>[" +
         label(k * bin) + ", " + label((k + 1) * bin) + "): " + std::to_string(counts[k]) +
         "</title></rect>\n";
  }
  s += "</g>\n";
  s += svg_axes(a, x_label + " (" + std::to_string(values.size()) + " values; bin " + label(bin) + ")",
                "count (points per bin)", 8, std::min(5, max_c));
  s += "</svg>\n";
  return s;
}

}  // namespace rangecal
